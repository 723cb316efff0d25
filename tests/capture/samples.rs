//! The real OpenFace samples with 3D landmarks (`../shared/openface-samples`): each is
//! captured with `--aus`, and the derived AU intensities are correlated with OpenFace's own
//! `AU*_r` beside a landmark-geometry baseline computed on the same pose-removed landmarks.
//! `cargo test --test capture samples -- --nocapture` prints the table of docs/capture.md.

use std::path::Path;

use glam::{DVec3, Vec3};
use grimace::capture::pose;
use grimace::io::openface::{OpenFaceReader, RowOutcome};

use crate::common;

const FILES: [&str; 2] = ["facsvatar_demo_faceid.csv", "pyfeat_OpenFace_Test.csv"];

/// The AUs compared, each with its geometric stand-in on the aligned landmarks (larger means
/// more of the AU).
const AUS: [(u8, &str); 7] = [
    (1, "inner brow height"),
    (2, "outer brow height"),
    (4, "inner brows drawn together"),
    (12, "lip-corner distance"),
    (25, "inner-lip gap"),
    (26, "chin to nasion"),
    (45, "eyelid aperture, negated"),
];

/// The AUs on which the muscles lead the geometry on the expressive sample (docs/capture.md):
/// held to within 0.02 of it, the most these AUs moved between the settings of the signed
/// reading's ridge that kept the jaw (AU4 0.883 to 0.906, AU45 0.865 to 0.885); AU25 since
/// it is read on both contours of the lips; the other (AU12, which trails it) to within 0.05.
const LEADING: [u8; 6] = [1, 2, 4, 25, 26, 45];

fn geometry(au: u8, p: &[DVec3]) -> f64 {
    let d = |a: usize, b: usize| p[a].distance(p[b]);
    match au {
        1 => 0.5 * (d(21, 39) + d(22, 42)),
        2 => 0.5 * (d(18, 36) + d(25, 45)),
        4 => -d(21, 22),
        12 => d(48, 54),
        25 => d(62, 66),
        26 => d(8, 27),
        _ => -0.25 * (d(37, 41) + d(38, 40) + d(43, 47) + d(44, 46)),
    }
}

fn pearson(a: &[f64], b: &[f64]) -> Option<f64> {
    let n = a.len().min(b.len()) as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let cov: f64 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
    let va: f64 = a.iter().map(|x| (x - ma).powi(2)).sum();
    let vb: f64 = b.iter().map(|y| (y - mb).powi(2)).sum();
    (va > 0.0 && vb > 0.0).then(|| cov / (va * vb).sqrt())
}

/// One frame's AU intensities, by AU number.
type Intensities = Vec<(u8, f64)>;

/// The recording's tracked rows: landmarks and OpenFace's AU intensities.
fn tracked(path: &Path) -> (Vec<Vec<Vec3>>, Vec<Intensities>) {
    let file = std::fs::File::open(path).unwrap();
    let mut reader = OpenFaceReader::with_landmarks(std::io::BufReader::new(file), path).unwrap();
    let numbers: Vec<u8> = reader.columns().aus.iter().map(|c| c.number).collect();
    let (mut points, mut aus) = (Vec::new(), Vec::new());
    while let Some(outcome) = reader.next_row().unwrap() {
        if let RowOutcome::Row(row) = outcome {
            if row.success {
                points.push(row.landmarks);
                let values = row.intensities.iter().map(|&v| f64::from(v));
                aus.push(numbers.iter().copied().zip(values).collect());
            }
        }
    }
    (points, aus)
}

/// The captured file's columns by name.
fn captured(text: &str) -> (Vec<String>, Vec<Vec<Option<f64>>>) {
    let mut lines = text.lines();
    let names = lines
        .next()
        .unwrap()
        .split(", ")
        .map(String::from)
        .collect();
    let rows = lines
        .map(|l| l.split(", ").map(|f| f.parse().ok()).collect())
        .collect();
    (names, rows)
}

#[test]
fn samples_are_captured_and_measured_against_openface_and_geometry() {
    let Some(dir) = common::shared_with(&["openface-samples"]) else {
        return;
    };
    let work = tempfile::tempdir().unwrap();
    for name in FILES {
        let path = dir.join("openface-samples").join(name);
        let out = common::grimace_in(
            work.path(),
            &[
                "capture",
                path.to_str().unwrap(),
                "--out",
                "acts.csv",
                "--aus",
            ],
        );
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let text = std::fs::read_to_string(work.path().join("acts.csv")).unwrap();
        let (names, rows) = captured(&text);
        let (points, openface) = tracked(&path);
        assert_eq!(
            rows.len(),
            points.len(),
            "{name}: one row per tracked frame"
        );
        let explained_at = names.iter().position(|n| n == "explained").unwrap();
        let mut explained: Vec<f64> = rows.iter().filter_map(|r| r[explained_at]).collect();
        explained.sort_by(f64::total_cmp);
        let median = explained[explained.len() / 2];
        assert!(
            (-1.0..=1.0).contains(&median),
            "{name}: median explained {median}"
        );
        let frames: Vec<&[Vec3]> = points.iter().map(Vec::as_slice).collect();
        let (neutral, _) = pose::estimate_neutral(&frames).unwrap();
        let aligned: Vec<Vec<DVec3>> = frames
            .iter()
            .map(|f| pose::align(f, &neutral).unwrap().points)
            .collect();
        eprintln!(
            "{name}: {} frames, median explained {median:.3} over {} above the noise floor",
            rows.len(),
            explained.len()
        );
        eprintln!("| AU | r (muscles) | r (geometry) | geometry |");
        for (au, what) in AUS {
            let column = names.iter().position(|n| *n == format!("AU{au:02}_r"));
            let theirs: Vec<f64> = openface
                .iter()
                .map(|r| r.iter().find(|(n, _)| *n == au).map_or(0.0, |(_, v)| *v))
                .collect();
            let ours: Option<Vec<f64>> =
                column.map(|c| rows.iter().map(|r| r[c].unwrap_or(0.0)).collect());
            let muscles = ours.and_then(|o| pearson(&o, &theirs));
            let shape: Vec<f64> = aligned.iter().map(|p| geometry(au, p)).collect();
            let baseline = pearson(&shape, &theirs);
            let show = |r: Option<f64>| r.map_or("-".to_string(), |r| format!("{r:.3}"));
            eprintln!(
                "| AU{au} | {} | {} | {what} |",
                show(muscles),
                show(baseline)
            );
            // Where the landmarks see the muscles well (brows, lids, the jaw, the lips), on
            // the expressive sample, the muscles keep up with the geometry. AU12 is held to
            // it since the neutral is the muscles' (the least-working frames), not this
            // smiling subject's typical face (docs/capture.md).
            if name == FILES[0] && [1, 2, 4, 12, 25, 26, 45].contains(&au) {
                let (m, g) = (muscles.unwrap(), baseline.unwrap());
                let margin = if LEADING.contains(&au) { 0.02 } else { 0.05 };
                assert!(
                    m >= g - margin,
                    "{name}: AU{au}: muscles r {m:.2}, geometry r {g:.2}"
                );
            }
        }
    }
}
