//! The example plan on a real single-node Slurm cluster: munge, slurmctld and slurmd started
//! on 127.0.0.1 from a configuration written in a temporary folder, the plan submitted as an
//! array of 4 shards with examples/slurm/batch.sbatch, one shard cancelled midway and
//! resubmitted alone, the merge as a dependent job; the result must equal a single-process
//! run byte for byte. The daemons are stopped by their process IDs, also when the test fails.
//!
//! Needs `sbatch` (Debian's slurm-wlm and munge); skipped with a reason without it, except
//! under CI=true, where it must run.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use super::*;

/// Whether a program is on PATH.
fn on_path(program: &str) -> bool {
    std::env::var_os("PATH")
        .is_some_and(|paths| std::env::split_paths(&paths).any(|dir| dir.join(program).is_file()))
}

/// A free TCP port on 127.0.0.1.
fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

fn text_of(command: &mut Command) -> String {
    let out = command
        .output()
        .unwrap_or_else(|e| panic!("{command:?}: {e}"));
    assert!(
        out.status.success(),
        "{command:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).trim().to_string()
}

/// The daemons this test started; dropping it cancels the cluster's jobs and stops them.
struct Cluster {
    dir: PathBuf,
    daemons: Vec<Child>,
}

impl Cluster {
    fn start(dir: &Path) -> Cluster {
        let mut cluster = Cluster {
            dir: dir.to_path_buf(),
            daemons: Vec::new(),
        };
        for sub in ["state", "spool", "logs"] {
            std::fs::create_dir_all(dir.join(sub)).unwrap();
        }
        let key = dir.join("munge.key");
        let mut bytes = vec![0u8; 1024];
        use std::io::Read;
        std::fs::File::open("/dev/urandom")
            .unwrap()
            .read_exact(&mut bytes)
            .unwrap();
        std::fs::write(&key, bytes).unwrap();
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&key, std::fs::Permissions::from_mode(0o400)).unwrap();
        let socket = dir.join("munge.sock");
        let path = |name: &str| dir.join(name).display().to_string();
        cluster.spawn(Command::new("munged").args([
            "--foreground".to_string(),
            "--force".to_string(),
            format!("--key-file={}", key.display()),
            format!("--socket={}", socket.display()),
            format!("--pid-file={}", path("munged.pid")),
            format!("--log-file={}", path("munged.log")),
            format!("--seed-file={}", path("munged.seed")),
        ]));
        let host = text_of(Command::new("hostname").arg("-s"));
        let user = text_of(Command::new("id").arg("-un"));
        let cpus = std::thread::available_parallelism().map_or(1, |n| n.get());
        let conf = format!(
            "ClusterName=grimacetest\nSlurmctldHost={host}(127.0.0.1)\nSlurmUser={user}\n\
             SlurmctldPort={}\nSlurmdPort={}\nAuthType=auth/munge\nCredType=cred/munge\n\
             AuthInfo=socket={}\nStateSaveLocation={}\nSlurmdSpoolDir={}\n\
             SlurmctldPidFile={}\nSlurmdPidFile={}\nSlurmctldLogFile={}\nSlurmdLogFile={}\n\
             ProctrackType=proctrack/linuxproc\nTaskPlugin=task/none\nSelectType=select/cons_tres\n\
             SelectTypeParameters=CR_CPU\nSchedulerType=sched/builtin\nReturnToService=2\n\
             MpiDefault=none\nMailProg=/bin/true\nJobCompType=jobcomp/none\n\
             JobAcctGatherType=jobacct_gather/none\nAccountingStorageType=accounting_storage/none\n\
             KillWait=5\nNodeName={host} NodeAddr=127.0.0.1 CPUs={cpus} State=UNKNOWN\n\
             PartitionName=test Nodes={host} Default=YES MaxTime=INFINITE State=UP\n",
            free_port(),
            free_port(),
            socket.display(),
            path("state"),
            path("spool"),
            path("slurmctld.pid"),
            path("slurmd.pid"),
            path("slurmctld.log"),
            path("slurmd.log"),
        );
        std::fs::write(dir.join("slurm.conf"), conf).unwrap();
        let start = Instant::now();
        while !socket.exists() {
            assert!(
                start.elapsed() < Duration::from_secs(20),
                "munged did not start"
            );
            std::thread::sleep(Duration::from_millis(50));
        }
        let conf = path("slurm.conf");
        cluster.spawn(Command::new("slurmctld").args(["-D", "-i", "-f", &conf]));
        cluster.spawn(Command::new("slurmd").args(["-D", "-f", &conf, "-N", &host]));
        cluster.wait_for("the node to be idle", Duration::from_secs(90), |c| {
            c.slurm("sinfo")
                .args(["-h", "-o", "%t"])
                .output()
                .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "idle")
        });
        cluster
    }

    fn spawn(&mut self, command: &mut Command) {
        let log = std::fs::File::create(
            self.dir
                .join("logs")
                .join(format!("daemon-{}.out", self.daemons.len())),
        )
        .unwrap();
        let child = command
            .stdout(log.try_clone().unwrap())
            .stderr(log)
            .stdin(Stdio::null())
            .spawn()
            .unwrap_or_else(|e| panic!("{command:?}: {e}"));
        self.daemons.push(child);
    }

    /// A Slurm client command for this cluster.
    fn slurm(&self, program: &str) -> Command {
        let mut command = Command::new(program);
        command.env("SLURM_CONF", self.dir.join("slurm.conf"));
        command
    }

    fn wait_for(&self, what: &str, limit: Duration, done: impl Fn(&Cluster) -> bool) {
        let start = Instant::now();
        while !done(self) {
            if start.elapsed() > limit {
                let log =
                    std::fs::read_to_string(self.dir.join("slurmctld.log")).unwrap_or_default();
                let tail: Vec<&str> = log.lines().rev().take(30).collect();
                panic!(
                    "timed out waiting for {what}; slurmctld.log ends:\n{}",
                    tail.into_iter().rev().collect::<Vec<_>>().join("\n")
                );
            }
            std::thread::sleep(Duration::from_millis(100));
        }
    }

    /// Waits until the cluster has no jobs left.
    fn wait_idle(&self, limit: Duration) {
        self.wait_for("the jobs to end", limit, |c| {
            c.slurm("squeue")
                .args(["-h", "-o", "%i"])
                .output()
                .is_ok_and(|o| o.status.success() && o.stdout.is_empty())
        });
    }

    /// Submits a batch script: the job ID.
    fn sbatch(&self, args: &[&str]) -> String {
        let id = text_of(
            self.slurm("sbatch")
                .args(["--parsable"])
                .args(args)
                .env("GRIMACE", env!("CARGO_BIN_EXE_grimace")),
        );
        id.split(';').next().unwrap().to_string()
    }
}

impl Drop for Cluster {
    fn drop(&mut self) {
        // Jobs first, so no job step outlives its daemon; then the daemons, newest first,
        // each by its process ID: asked to stop, then killed if it has not within 10 s.
        let _ = self.slurm("scancel").args(["--partition", "test"]).output();
        for child in self.daemons.iter_mut().rev() {
            let _ = Command::new("kill")
                .args(["-TERM", &child.id().to_string()])
                .output();
            let start = Instant::now();
            while child.try_wait().ok().flatten().is_none()
                && start.elapsed() < Duration::from_secs(10)
            {
                std::thread::sleep(Duration::from_millis(50));
            }
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

#[test]
fn the_example_plan_runs_as_a_slurm_array_with_a_cancelled_shard_resubmitted() {
    if !on_path("sbatch") || !on_path("slurmctld") || !on_path("munged") {
        assert!(
            std::env::var("CI").as_deref() != Ok("true"),
            "CI=true: Slurm (sbatch, slurmctld, slurmd, munged) must be installed: apt-get install slurm-wlm munge"
        );
        eprintln!("skipped: Slurm is not installed (apt-get install slurm-wlm munge)");
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    // Pictures large enough (a shard of 84 items takes about 2 s on one core of an optimised
    // build) that shard 2 is still running when it is cancelled: with the tiny ones a fast
    // build finished the shard between the poll that saw it start and the cancel.
    let plan = example_sized(tmp.path(), 768);
    let one = tmp.path().join("one");
    let out = run(&[
        plan.as_os_str(),
        "--out".as_ref(),
        one.as_os_str(),
        "--jobs".as_ref(),
        "2".as_ref(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(run(&["merge".as_ref(), one.as_os_str()]).status.success());

    let cluster = Cluster::start(&tmp.path().join("slurm"));
    let scripts = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/slurm");
    let batch_script = scripts.join("batch.sbatch").display().to_string();
    let merge_script = scripts.join("merge.sbatch").display().to_string();
    let four = tmp.path().join("four");
    let (plan_arg, four_arg) = (plan.display().to_string(), four.display().to_string());
    let logs = format!(
        "--output={}/%x-%A_%a.out",
        tmp.path().join("slurm/logs").display()
    );
    let array = cluster.sbatch(&[
        "--array=0-3",
        "--cpus-per-task=1",
        &logs,
        &batch_script,
        &plan_arg,
        &four_arg,
    ]);
    // Shard 2 cancelled once it has made a few items.
    let rows = four.join("labels/shard-00002-of-00004.csv");
    cluster.wait_for("shard 2 to start", Duration::from_secs(180), |_| {
        std::fs::read_to_string(&rows).is_ok_and(|t| t.lines().count() > 3)
    });
    text_of(cluster.slurm("scancel").arg(format!("{array}_2")));
    cluster.wait_idle(Duration::from_secs(300));
    let early = run(&["merge".as_ref(), four.as_os_str()]);
    assert_eq!(
        early.status.code(),
        Some(1),
        "shard 2 was not cut short: {}",
        stderr(&early)
    );

    let again = cluster.sbatch(&[
        "--array=2",
        "--cpus-per-task=1",
        "--export=ALL,SHARD=slurm/4",
        &logs,
        &batch_script,
        &plan_arg,
        &four_arg,
    ]);
    let merge_log = format!(
        "--output={}/merge-%j.out",
        tmp.path().join("slurm/logs").display()
    );
    cluster.sbatch(&[
        &format!("--dependency=afterok:{again}"),
        &merge_log,
        &merge_script,
        &four_arg,
    ]);
    cluster.wait_idle(Duration::from_secs(300));
    assert!(
        four.join("labels.csv").is_file(),
        "the merge job wrote no labels"
    );
    let logs: String = std::fs::read_dir(tmp.path().join("slurm/logs"))
        .unwrap()
        .filter_map(|e| std::fs::read_to_string(e.ok()?.path()).ok())
        .collect();
    assert!(
        logs.contains("shard 2/4:") && logs.contains("already done"),
        "{logs}"
    );
    assert!(logs.contains("merged 336 items"), "{logs}");
    assert_same_batch(&one, &four);
}
