//! AU shapes on the default face, measured: how far (mm) and which way each AU moves the
//! tissue FACS says it moves. The numbers are the golden values of `docs/au.md`; run with
//! `--nocapture` to print them.

use glam::Vec3;
use grimace::face::anthropometry::MM_PER_UNIT;
use grimace::face::{au_table, generate, rigs};
use grimace::facs::combo::parse_combo;
use grimace::facs::AuTable;
use grimace::model::{Activations, BoundRig, Mesh, Rig, SkinRules};

pub(crate) struct Face {
    pub(crate) mesh: Mesh,
    pub(crate) rig: Rig,
    pub(crate) table: AuTable,
    pub(crate) bound: BoundRig,
}

pub(crate) fn face() -> Face {
    let mesh = generate();
    let rig = rigs::default_rig(&mesh).expect("default rig places");
    let bound = BoundRig::bind_with(&rig, &mesh, SkinRules::DEFAULT).expect("default rig binds");
    Face {
        mesh,
        rig,
        table: au_table::default_table(),
        bound,
    }
}

pub(crate) const MM: f32 = MM_PER_UNIT as f32;

impl Face {
    pub(crate) fn combo(&self, text: &str) -> Vec<Vec3> {
        let combo = parse_combo(text).expect("combination parses");
        let act = self.table.evaluate(&combo, &self.rig).expect("evaluates");
        self.deform(&act)
    }

    pub(crate) fn deform(&self, act: &Activations) -> Vec<Vec3> {
        let mut out = Vec::new();
        self.bound.deform(act, &mut out).expect("valid activations");
        assert!(out.iter().all(|p| p.is_finite()));
        out
    }

    pub(crate) fn group(&self, name: &str) -> &[u32] {
        self.mesh
            .groups
            .get(name)
            .unwrap_or_else(|| panic!("no group {name}"))
    }

    pub(crate) fn vertex(&self, name: &str) -> usize {
        match self.group(name) {
            [v] => *v as usize,
            _ => panic!("{name} is not a landmark"),
        }
    }

    /// Displacement of a landmark in mm.
    pub(crate) fn moved(&self, pose: &[Vec3], name: &str) -> Vec3 {
        let v = self.vertex(name);
        (pose[v] - self.mesh.positions[v]) * MM
    }

    /// Mean displacement (mm) of a group's members, optionally only those with `x > 0`
    /// (the subject's left) or `x < 0`.
    pub(crate) fn region(&self, pose: &[Vec3], name: &str, side: Option<bool>) -> Vec3 {
        let members: Vec<usize> = self
            .group(name)
            .iter()
            .map(|&v| v as usize)
            .filter(|&v| match side {
                Some(left) => (self.mesh.positions[v].x > 0.0) == left,
                None => true,
            })
            .collect();
        let sum: Vec3 = members
            .iter()
            .map(|&v| pose[v] - self.mesh.positions[v])
            .sum();
        sum * MM / members.len() as f32
    }

    /// Pairs of (upper, lower) lid margin vertices of the left eye at about the same x.
    fn lid_pairs(&self) -> Vec<(usize, usize)> {
        let rest = &self.mesh.positions;
        let lower = self.group("left_lower_lid");
        self.group("left_upper_lid")
            .iter()
            .filter_map(|&u| {
                let u = u as usize;
                let l = *lower.iter().min_by(|&&a, &&b| {
                    let da = (rest[a as usize].x - rest[u].x).abs();
                    let db = (rest[b as usize].x - rest[u].x).abs();
                    da.total_cmp(&db)
                })? as usize;
                (u != l && (rest[l].x - rest[u].x).abs() < 0.05).then_some((u, l))
            })
            .collect()
    }

    /// The left eye's opening at its middle (upper minus lower lid centre height, mm).
    fn opening(&self, pose: &[Vec3]) -> f32 {
        (pose[self.vertex("left_upper_lid_centre")].y
            - pose[self.vertex("left_lower_lid_centre")].y)
            * MM
    }

    /// The lips' gap at the middle (upper minus lower lip centre height, mm; negative when
    /// the lower lip rises past the upper).
    fn mouth_gap(&self, pose: &[Vec3]) -> f32 {
        (pose[self.vertex("upper_lip_centre")].y - pose[self.vertex("lower_lip_centre")].y) * MM
    }

    /// How far (mm) the lower lid margin rises above the upper one anywhere (0 if never).
    fn crossing(&self, pose: &[Vec3]) -> f32 {
        self.lid_pairs()
            .iter()
            .map(|&(u, l)| (pose[l].y - pose[u].y) * MM)
            .fold(0.0, f32::max)
    }

    /// Triangles whose front-facing normal turned by more than 90 degrees.
    pub(crate) fn flips(&self, pose: &[Vec3]) -> usize {
        let normal = |p: &[Vec3], t: &[u32; 3]| {
            let [a, b, c] = t.map(|v| p[v as usize]);
            (b - a).cross(c - a)
        };
        self.mesh
            .triangles
            .iter()
            .filter(|t| normal(pose, t).dot(normal(&self.mesh.positions, t)) <= 0.0)
            .count()
    }
}

fn show(label: &str, v: Vec3) {
    println!("{label:40} x {:6.2}  y {:6.2}  z {:6.2} mm", v.x, v.y, v.z);
}

/// The FACS direction of the clearest point of each AU (docs/au.md): the chin and lower lip
/// drop with the jaw, the upper lid closes down and opens up, the brows lower and raise, the
/// mouth corners rise and fall, the upper lip rises. (`--nocapture` prints the moves, mm.)
#[test]
fn each_au_moves_its_own_point_the_facs_way() {
    let f = face();
    let up = |au: &str, point: &str| {
        let v = f.moved(&f.combo(au), point);
        show(&format!("AU{au} {point}"), v);
        v.y
    };
    for au in ["26", "27"] {
        assert!(up(au, "chin") < -1.0, "AU{au}: the chin drops");
        assert!(
            up(au, "lower_lip_centre") < -1.0,
            "AU{au}: the lower lip drops"
        );
    }
    for au in ["43", "45"] {
        assert!(
            up(au, "left_upper_lid_centre") < -1.0,
            "AU{au}: the upper lid closes"
        );
    }
    assert!(
        up("5", "left_upper_lid_centre") > 0.3,
        "AU5: the upper lid rises"
    );
    assert!(
        up("4", "left_brow_inner") < -0.3,
        "AU4: the inner brow lowers"
    );
    assert!(
        up("1", "left_brow_inner") > 0.3,
        "AU1: the inner brow rises"
    );
    assert!(
        f.region(&f.combo("2"), "left_brow", Some(true)).y > 0.3,
        "AU2: the brow rises"
    );
    assert!(
        up("12", "left_mouth_corner") > 0.3,
        "AU12: the corner rises"
    );
    assert!(
        up("15", "left_mouth_corner") < -0.3,
        "AU15: the corner falls"
    );
    assert!(
        up("10", "upper_lip_centre") > 0.3,
        "AU10: the upper lip rises"
    );
}

#[test]
fn jaw_drop_moves_the_chin_mostly_down_and_opens_an_oval() {
    let f = face();
    // (AU, chin drop at least, lower lip drop at least) in mm
    for (au, chin_drop, lip_drop) in [("26", 12.0, 12.0), ("27", 18.0, 20.0)] {
        let p = f.combo(au);
        let chin = f.moved(&p, "chin");
        assert!(
            -chin.y > chin_drop && -chin.y > 1.4 * -chin.z && chin.z < 0.0,
            "AU{au}: chin {chin} mm should move mostly down, a little back"
        );
        let lip = f.moved(&p, "lower_lip_centre");
        assert!(-lip.y > lip_drop, "AU{au}: lower lip drops {lip}");
        for (corner, outward) in [("left_mouth_corner", 1.0), ("right_mouth_corner", -1.0)] {
            let c = f.moved(&p, corner);
            // drawn in and down: below rest, by less than half the lower lip's drop (the
            // skin round the corner carries the opening, so it does not tear there)
            assert!(c.x * outward < -0.5, "AU{au}: {corner} drawn in: {c}");
            assert!(
                c.y < -1.0 && c.y > 0.45 * lip.y,
                "AU{au}: {corner} slightly down: {c}"
            );
        }
        // an oval: halfway to the corner the lower lip has dropped more than 60 % as far as
        // its middle (a crescent keeps the sides nearly shut; the jaw's weights rise in
        // proportion to the distance from the corner so the corners do not tear, 66 % at
        // AU26)
        let rest = &f.mesh.positions;
        let corner_x = rest[f.vertex("left_mouth_corner")].x;
        let lower = f.group("lower_lip");
        let upper = f.group("upper_lip");
        let margin_near = |group: &[u32], top: bool| {
            *group
                .iter()
                .filter(|&&v| {
                    let x = rest[v as usize].x;
                    (x - 0.5 * corner_x).abs() < 0.1 * corner_x
                })
                .min_by(|&&a, &&b| {
                    let key = |v: u32| {
                        let y = rest[v as usize].y;
                        if top {
                            y
                        } else {
                            -y
                        }
                    };
                    key(a).total_cmp(&key(b))
                })
                .expect("lip margin halfway to the corner") as usize
        };
        let (u, l) = (margin_near(upper, true), margin_near(lower, false));
        let middle = (p[f.vertex("upper_lip_centre")].y - p[f.vertex("lower_lip_centre")].y) * MM;
        let side = (p[u].y - p[l].y) * MM;
        assert!(
            side > 0.6 * middle,
            "AU{au}: opening halfway to the corner {side} mm of {middle} mm at the middle"
        );
    }
}

#[test]
fn the_upper_lid_carries_a_blink_and_the_lids_never_cross() {
    let f = face();
    let rest_opening = f.opening(&f.mesh.positions);
    for au in ["43", "45"] {
        for letter in ["A", "B", "C", "D", "E"] {
            let p = f.combo(&format!("{au}{letter}"));
            assert!(f.crossing(&p) <= 0.0, "AU{au}{letter}: lids cross");
        }
        let p = f.combo(au);
        let up = -f.moved(&p, "left_upper_lid_centre").y;
        let low = f.moved(&p, "left_lower_lid_centre").y;
        assert!(
            up / (up + low) >= 0.8,
            "AU{au}: upper lid {up} mm, lower {low} mm"
        );
        assert!(
            f.opening(&p) < 0.5,
            "AU{au}: eye still {} mm open",
            f.opening(&p)
        );
        assert!(f.opening(&p) >= 0.0);
        assert_eq!(f.flips(&p), 0, "AU{au}: flipped triangles");
    }
    // AU5 shows more of the eye; AU7 narrows it mainly from below
    let p = f.combo("5");
    assert!(
        f.opening(&p) > rest_opening + 3.0,
        "AU5: {} mm",
        f.opening(&p)
    );
    let p = f.combo("7");
    let up = -f.moved(&p, "left_upper_lid_centre").y;
    let low = f.moved(&p, "left_lower_lid_centre").y;
    assert!(
        low > 2.5 && low > 2.0 * up,
        "AU7: lower lid {low} mm, upper {up} mm"
    );
}

#[test]
fn no_au_flips_a_triangle_at_full_intensity() {
    let f = face();
    for k in f.table.aus.keys() {
        let p = f.combo(&k.to_string());
        assert_eq!(f.flips(&p), 0, "AU{k} flips triangles");
    }
}

/// Asserts a displacement (mm) is within `tol` mm of its golden value in every coordinate.
fn golden(label: &str, got: Vec3, want: [f32; 3], tol: f32) {
    let want = Vec3::from(want);
    assert!(
        (got - want).abs().max_element() <= tol,
        "{label}: {got} mm, golden {want} mm"
    );
}

#[test]
fn the_lip_aus_move_the_middle_of_their_lip() {
    let f = face();
    // AU10: the whole upper lip rises, its middle more than the corner; the lower lip stays
    // and the lips part
    let p = f.combo("10");
    golden(
        "AU10 upper lip centre",
        f.moved(&p, "upper_lip_centre"),
        [0.0, 4.54, 1.90],
        0.3,
    );
    golden(
        "AU10 upper lip (left)",
        f.region(&p, "upper_lip", Some(true)),
        [2.32, 6.45, -0.51],
        0.3,
    );
    golden(
        "AU10 lower lip centre",
        f.moved(&p, "lower_lip_centre"),
        [0.0, 0.0, 0.0],
        0.05,
    );
    // AU9: the ala rises (hardly flaring) and takes the upper lip up with it
    let p = f.combo("9");
    golden(
        "AU9 left alare",
        f.moved(&p, "left_alare"),
        [0.41, 7.40, -3.35],
        0.3,
    );
    golden(
        "AU9 upper lip centre",
        f.moved(&p, "upper_lip_centre"),
        [0.0, 2.34, 1.28],
        0.3,
    );
    // AU16: the lower lip's middle drops; the upper lip stays
    let p = f.combo("16");
    golden(
        "AU16 lower lip centre",
        f.moved(&p, "lower_lip_centre"),
        [0.0, -4.63, 1.55],
        0.3,
    );
    golden(
        "AU16 lower lip (left)",
        f.region(&p, "lower_lip", Some(true)),
        [0.29, -5.26, -1.26],
        0.3,
    );
    golden(
        "AU16 upper lip centre",
        f.moved(&p, "upper_lip_centre"),
        [0.0, 0.0, 0.0],
        0.05,
    );
    // AU17: the chin boss rises and comes forward, the lower lip is pushed up against the
    // upper one and out
    let p = f.combo("17");
    golden("AU17 chin", f.moved(&p, "chin"), [0.0, 5.97, 2.09], 0.3);
    golden(
        "AU17 lower lip centre",
        f.moved(&p, "lower_lip_centre"),
        [0.0, 0.61, 1.08],
        0.2,
    );
    golden(
        "AU17 lower lip (left)",
        f.region(&p, "lower_lip", Some(true)),
        [-0.50, 1.63, 1.51],
        0.3,
    );
    // no lip AU pushes the lower lip through the upper one
    // AU18, 23 and 24 differ in shape (see also
    // `lip_pucker_tightener_and_presser_differ_in_shape`): 18 draws the corners in and pushes
    // the lips forward, 23 thins both lips toward the mouth line with the corners nearly
    // still, 24 presses the lips together and the lower lip up from the chin
    let p = f.combo("18");
    golden(
        "AU18 corner",
        f.moved(&p, "left_mouth_corner"),
        [-4.30, 0.0, 1.32],
        0.3,
    );
    golden(
        "AU18 upper lip centre",
        f.moved(&p, "upper_lip_centre"),
        [0.0, 0.0, 3.72],
        0.2,
    );
    let p = f.combo("23");
    golden(
        "AU23 corner",
        f.moved(&p, "left_mouth_corner"),
        [-1.08, 0.0, 0.38],
        0.3,
    );
    golden(
        "AU23 upper lip (left)",
        f.region(&p, "upper_lip", Some(true)),
        [-0.30, -1.38, 0.68],
        0.3,
    );
    golden(
        "AU23 lower lip (left)",
        f.region(&p, "lower_lip", Some(true)),
        [-0.27, 1.69, 0.61],
        0.3,
    );
    let p = f.combo("24");
    golden("AU24 chin", f.moved(&p, "chin"), [0.0, 4.34, 1.52], 0.3);
    golden(
        "AU24 lower lip centre",
        f.moved(&p, "lower_lip_centre"),
        [0.0, 0.53, 1.23],
        0.2,
    );
    for au in ["9", "10", "16", "17", "18", "23", "24"] {
        let p = f.combo(au);
        assert!(
            f.mouth_gap(&p) >= -0.05,
            "AU{au}: lips cross by {} mm",
            -f.mouth_gap(&p)
        );
    }
}

#[test]
fn brow_lowerer_draws_the_brows_down_and_together() {
    let f = face();
    let p = f.combo("4");
    // the head of the brow: in toward the midline and down (it reads as a frown with
    // vertical furrows between the brows)
    golden(
        "AU4 brow inner",
        f.moved(&p, "left_brow_inner"),
        [-2.53, -10.06, -0.96],
        0.3,
    );
    golden(
        "AU4 brow (left)",
        f.region(&p, "left_brow", Some(true)),
        [-1.36, -8.32, -0.06],
        0.3,
    );
    // one-sided: the left brow only
    let p = f.combo("L4");
    let right = f.moved(&p, "right_brow_inner");
    assert!(
        right.length() < 0.5,
        "L4 moves the right brow head {right} mm"
    );
}

impl Face {
    /// Height (mm) of the red of both lips at the middle: from the upper vermilion's top to
    /// the lower vermilion's bottom within 2 mm of the midline, less the gap between the lips.
    fn red_height(&self, pose: &[Vec3]) -> f32 {
        let near = |v: &&u32| self.mesh.positions[**v as usize].x.abs() < 2.0 / MM;
        let top = self
            .group("upper_lip")
            .iter()
            .filter(near)
            .map(|&v| pose[v as usize].y)
            .fold(f32::NEG_INFINITY, f32::max);
        let bottom = self
            .group("lower_lip")
            .iter()
            .filter(near)
            .map(|&v| pose[v as usize].y)
            .fold(f32::INFINITY, f32::min);
        (top - bottom) * MM - self.mouth_gap(pose).max(0.0)
    }

    /// Mean forward travel (mm, toward the viewer) of the red of both lips.
    fn lips_forward(&self, pose: &[Vec3]) -> f32 {
        let lips: Vec<u32> = [self.group("upper_lip"), self.group("lower_lip")].concat();
        let sum: f32 = lips
            .iter()
            .map(|&v| pose[v as usize].z - self.mesh.positions[v as usize].z)
            .sum();
        sum * MM / lips.len() as f32
    }
}

/// AU18 (pucker), AU23 (tightener) and AU24 (presser) differ in shape, not only strength:
/// the forward push of the lips, how far the corners travel in, and the red's height.
#[test]
fn lip_pucker_tightener_and_presser_differ_in_shape() {
    let f = face();
    let rest_red = f.red_height(&f.mesh.positions);
    let shape = |au: &str| {
        let p = f.combo(au);
        let inward = -f.moved(&p, "left_mouth_corner").x;
        let forward = f.lips_forward(&p);
        let red = f.red_height(&p) - rest_red;
        let chin = f.moved(&p, "chin").y;
        println!(
            "AU{au}: lips forward {forward:.2} mm, corner in {inward:.2} mm, red height \
             {red:+.2} mm (rest {rest_red:.2}), chin up {chin:.2} mm"
        );
        (forward, inward, red, chin)
    };
    let (f18, in18, red18, _) = shape("18");
    let (f23, in23, red23, chin23) = shape("23");
    let (f24, in24, red24, chin24) = shape("24");
    // 18 pushes the lips forward and draws the corners in the most; the red keeps its height
    assert!(
        f18 > 1.5 * f23 && f18 > 1.5 * f24,
        "pucker forward {f18}, {f23}, {f24}"
    );
    assert!(in18 > 3.0 * in23.max(in24), "pucker corners {in18}");
    assert!(red18.abs() < 1.0, "pucker red {red18}");
    // 23 thins the red toward the mouth line with the corners nearly still, the chin still
    assert!(
        red23 < -3.0 && in23 < 1.5,
        "tightener red {red23}, corners {in23}"
    );
    assert!(chin23.abs() < 0.5, "tightener chin {chin23}");
    // 24 presses the lips together from below: the red flattened, the chin pushed up (the
    // bulge below the lower lip), the corners hardly moving
    assert!(
        red24 < -3.0 && chin24 > 3.0,
        "presser red {red24}, chin {chin24}"
    );
    assert!(in24 < in23, "presser corners {in24}");
}

/// Contempt (`R12C+R14B`) raises the right mouth corner at least 4 mm, as FACS describes a
/// one-sided raise (`docs/au.md`; the prototype's trace letters `R12A+R14A` raised it 1.3 mm),
/// and leaves the left corner.
#[test]
fn contempt_raises_the_right_corner_visibly() {
    let f = face();
    let combo = &f.table.expressions["contempt"];
    let p = f.combo(combo);
    let right = f.moved(&p, "right_mouth_corner");
    let left = f.moved(&p, "left_mouth_corner");
    let front = Vec3::new(right.x, right.y, 0.0).length();
    println!("{combo}: right corner {right} mm ({front:.2} mm in the front view)");
    assert!(right.y >= 4.0, "the right corner rises {} mm", right.y);
    assert!(left.length() < 0.3, "the left corner moves {left} mm");
}

/// AU1 lifts the head of the brow as a band: at least 7.5 mm (the linear `Frontalis_Inner`
/// raised it 6.0 mm with the forehead's middle moving most), the glabella between the heads
/// at least half as far (no dent at the midline), and the tail of the brow under 2 mm.
#[test]
fn inner_brow_raiser_lifts_the_head_of_the_brow_as_a_band() {
    let f = face();
    let p = f.combo("1");
    let head = f.moved(&p, "left_brow_inner");
    let tail = f.moved(&p, "left_brow_outer");
    let (l, r) = (
        f.moved(&p, "left_brow_inner"),
        f.moved(&p, "right_brow_inner"),
    );
    println!("AU1: head of the brow {head} mm, tail {tail} mm");
    assert!(head.y >= 7.5, "the head of the brow rises {} mm", head.y);
    assert!(tail.y < 2.0, "the tail of the brow rises {} mm", tail.y);
    assert!((l.y - r.y).abs() < 1e-3, "both heads rise alike");
    // the glabella: the midline skin vertex level with the heads of the brows
    let brow_y = f.mesh.positions[f.vertex("left_brow_inner")].y;
    let skin = grimace::face::groups::skin_len(&f.mesh);
    let g = (0..skin)
        .filter(|&v| f.mesh.positions[v].x == 0.0)
        .min_by(|&a, &b| {
            let d = |v: usize| (f.mesh.positions[v].y - brow_y).abs();
            d(a).total_cmp(&d(b))
        })
        .expect("a midline vertex");
    let glabella = (p[g] - f.mesh.positions[g]) * MM;
    println!("AU1: glabella {glabella} mm");
    assert!(
        glabella.y >= 0.5 * head.y,
        "the glabella rises {} mm, the heads {} mm",
        glabella.y,
        head.y
    );
}

/// An open jaw sinks the mouth corners with the lower lip, at least a third of its drop (an
/// oval opening: with the corners held high the tracker read AU26 as a smile).
#[test]
fn an_open_jaw_sinks_the_corners_with_the_lower_lip() {
    let f = face();
    let p = f.combo("26");
    let corner = f.moved(&p, "left_mouth_corner");
    let lip = f.moved(&p, "lower_lip_centre");
    println!("AU26: corner {corner} mm, lower lip {lip} mm");
    assert!(
        corner.y <= lip.y / 3.0,
        "the corner sinks {} mm for the lip's {} mm",
        -corner.y,
        -lip.y
    );
}

/// Sadness shows the oblique brows of AU1+4: the head of the brow up, the tail of the brow
/// not up, so the brow slants down toward the temple. Its AU4 is a trace (4A): a stronger 4
/// lowers the whole brow and takes the inner brow raise back (`docs/au.md`), so the heads
/// are drawn together only a little and stay over the eyes.
#[test]
fn sadness_slants_the_brows() {
    let f = face();
    let act = f
        .table
        .expression_activations("sadness", &f.rig)
        .expect("sadness");
    let p = f.deform(&act);
    let inner = f.moved(&p, "left_brow_inner");
    let outer = f.moved(&p, "left_brow_outer");
    println!("sadness: head of the left brow {inner} mm, tail {outer} mm");
    assert!(inner.y > 2.5, "the head of the brow rises {} mm", inner.y);
    assert!(
        inner.x.abs() < 1.0,
        "the head of the brow moves sideways {} mm",
        inner.x
    );
    assert!(outer.y < 1.0, "the tail of the brow rises {} mm", outer.y);
    assert!(inner.y - outer.y > 2.0, "the brow hardly slants");
}
