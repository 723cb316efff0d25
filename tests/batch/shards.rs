//! Sharding gives byte-identical results; a shard killed with SIGKILL resumes.

use std::ffi::OsStr;
use std::time::{Duration, Instant};

use super::*;

#[test]
fn one_shard_and_three_shards_with_a_killed_one_give_the_same_batch() {
    let tmp = tempfile::tempdir().unwrap();
    let plan = small_example(tmp.path());
    let (one, three) = (tmp.path().join("one"), tmp.path().join("three"));
    let out = run(&[
        plan.as_os_str(),
        "--out".as_ref(),
        one.as_os_str(),
        "--jobs".as_ref(),
        "2".as_ref(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let merged = run(&["merge".as_ref(), one.as_os_str()]);
    assert!(merged.status.success(), "{}", stderr(&merged));

    let shard = |k: &str| -> Vec<std::ffi::OsString> {
        vec![
            plan.clone().into(),
            "--out".into(),
            three.clone().into(),
            "--shard".into(),
            k.into(),
            "--jobs".into(),
            "1".into(),
        ]
    };
    for k in ["0/3", "2/3"] {
        let args = shard(k);
        let out = run(&args.iter().map(|a| a.as_os_str()).collect::<Vec<_>>());
        assert!(out.status.success(), "{}", stderr(&out));
    }
    // Shard 1 killed (SIGKILL) once it has finished a few items.
    let args = shard("1/3");
    let args: Vec<&OsStr> = args.iter().map(|a| a.as_os_str()).collect();
    let mut child = batch(&args)
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let rows = three.join("labels/shard-00001-of-00003.csv");
    let start = Instant::now();
    while std::fs::read_to_string(&rows).map_or(0, |t| t.lines().count()) < 5 {
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "shard 1 made nothing"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    assert!(
        child.try_wait().unwrap().is_none(),
        "shard 1 finished before it could be killed"
    );
    child.kill().unwrap();
    child.wait().unwrap();

    let early = run(&["merge".as_ref(), three.as_os_str()]);
    assert_eq!(
        early.status.code(),
        Some(1),
        "a merge with a shard unfinished must fail"
    );
    assert!(
        stderr(&early).contains("missing or damaged"),
        "{}",
        stderr(&early)
    );
    assert!(!three.join("labels.csv").exists());

    let resumed = run(&args);
    let text = stderr(&resumed);
    assert!(resumed.status.success(), "{text}");
    let skipped: usize = text
        .split(" made, ")
        .nth(1)
        .and_then(|t| t.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no summary: {text}"));
    assert!(skipped >= 4, "the rerun redid finished items: {text}");
    let merged = run(&["merge".as_ref(), three.as_os_str()]);
    assert!(merged.status.success(), "{}", stderr(&merged));
    let leftovers: Vec<_> = files_under(&three)
        .into_iter()
        .filter(|p| p.to_string_lossy().contains(".tmp-"))
        .collect();
    assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");
    assert_same_batch(&one, &three);
    let labels = std::fs::read_to_string(one.join("labels.csv")).unwrap();
    assert_eq!(
        labels.lines().count(),
        1 + 336,
        "the example plan's item count changed"
    );
}

#[test]
fn a_rerun_of_a_finished_shard_makes_nothing_and_a_damaged_file_is_made_again() {
    let tmp = tempfile::tempdir().unwrap();
    let plan = plan(tmp.path(), TINY);
    let out_dir = tmp.path().join("out");
    let args = [plan.as_os_str(), "--out".as_ref(), out_dir.as_os_str()];
    assert!(run(&args).status.success());
    let labels = std::fs::read_to_string(out_dir.join("items.csv")).unwrap();
    let png = labels
        .lines()
        .find(|l| l.contains(".png"))
        .unwrap()
        .split(',')
        .nth(12)
        .unwrap()
        .to_string();
    std::fs::write(out_dir.join(&png), b"damaged").unwrap();
    let again = run(&args);
    assert!(
        stderr(&again).contains("1 made, 3 already done"),
        "{}",
        stderr(&again)
    );
    assert!(run(&["merge".as_ref(), out_dir.as_os_str()])
        .status
        .success());
    assert!(std::fs::read(out_dir.join(&png))
        .unwrap()
        .starts_with(b"\x89PNG"));
}

#[test]
fn a_full_disk_stops_with_the_file_named_and_keeps_what_was_finished() {
    let tmp = tempfile::tempdir().unwrap();
    let plan = plan(tmp.path(), TINY);
    let out_dir = tmp.path().join("out");
    // Files above 4 KiB fail as on a full disk: the text files fit, the PNGs do not.
    let full = std::process::Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -f 8 && exec \"$0\" batch {} --out {} --jobs 1",
            plan.display(),
            out_dir.display()
        ))
        .arg(env!("CARGO_BIN_EXE_grimace"))
        .output()
        .unwrap();
    let text = stderr(&full);
    assert_eq!(full.status.code(), Some(1), "{text}");
    assert!(
        text.contains(".png") && text.contains("cannot save"),
        "{text}"
    );
    let again = run(&[plan.as_os_str(), "--out".as_ref(), out_dir.as_os_str()]);
    assert!(
        stderr(&again).contains("2 made, 2 already done"),
        "{}",
        stderr(&again)
    );
}

#[test]
fn slurm_array_environment_picks_the_shard() {
    let tmp = tempfile::tempdir().unwrap();
    let plan = plan(tmp.path(), TINY);
    let out_dir = tmp.path().join("out");
    for id in ["3", "4"] {
        let out = batch(&[
            plan.as_os_str(),
            "--out".as_ref(),
            out_dir.as_os_str(),
            "--shard".as_ref(),
            "slurm".as_ref(),
        ])
        .env("SLURM_ARRAY_TASK_ID", id)
        .env("SLURM_ARRAY_TASK_MIN", "3")
        .env("SLURM_ARRAY_TASK_MAX", "4")
        .env("SLURM_ARRAY_TASK_COUNT", "2")
        .env("SLURM_CPUS_PER_TASK", "1")
        .output()
        .unwrap();
        assert!(out.status.success(), "{}", stderr(&out));
        assert!(stderr(&out).contains("on 1 threads"), "{}", stderr(&out));
    }
    assert!(out_dir.join("labels/shard-00000-of-00002.csv").is_file());
    assert!(out_dir.join("labels/shard-00001-of-00002.csv").is_file());
    assert!(run(&["merge".as_ref(), out_dir.as_os_str()])
        .status
        .success());
}

#[test]
fn dry_run_counts_and_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let plan = small_example(tmp.path());
    let out_dir = tmp.path().join("out");
    let out = run(&[
        plan.as_os_str(),
        "--out".as_ref(),
        out_dir.as_os_str(),
        "--dry-run".as_ref(),
        "--shard".as_ref(),
        "1/4".as_ref(),
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        text.contains("336 items") && text.contains("--array=0-"),
        "{text}"
    );
    assert!(!out_dir.exists());
}

#[test]
fn ctrl_c_stops_after_the_items_being_drawn_and_a_rerun_finishes() {
    let tmp = tempfile::tempdir().unwrap();
    let plan = small_example(tmp.path());
    let out_dir = tmp.path().join("out");
    let args = [
        plan.as_os_str(),
        "--out".as_ref(),
        out_dir.as_os_str(),
        "--shard".as_ref(),
        "0/2".as_ref(),
        "--jobs".as_ref(),
        "1".as_ref(),
    ];
    let child = batch(&args)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let rows = out_dir.join("labels/shard-00000-of-00002.csv");
    let start = Instant::now();
    while std::fs::read_to_string(&rows).map_or(0, |t| t.lines().count()) < 3 {
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "the shard made nothing"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    let interrupted = std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(interrupted.success());
    let out = child.wait_with_output().unwrap();
    let text = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{text}");
    assert!(text.contains("stopped early"), "{text}");
    let made: usize = text
        .split("shard 0/2: ")
        .last()
        .and_then(|t| t.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("{text}"));
    let kept = std::fs::read_to_string(&rows).unwrap().lines().count() - 1;
    assert_eq!(kept, made, "every item made has its row: {text}");
    let again = run(&args);
    assert!(again.status.success(), "{}", stderr(&again));
    assert!(
        stderr(&again).contains(&format!("{made} already done")),
        "{}",
        stderr(&again)
    );
}
