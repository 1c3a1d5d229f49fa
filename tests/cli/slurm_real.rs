//! The Slurm workflow on a real single-node Slurm: munged, slurmctld and slurmd started on
//! the loopback address from a scratch `slurm.conf`, `scripts/slurm/submit.sh` submitting
//! a small sweep with the binary already built (no build job), `squeue` polled until the
//! array and the merge are done, and the merged summary compared with the unsharded
//! sweep number for number. The daemons are stopped whatever happens (a guard's `Drop`).
//!
//! It needs root and Debian's `slurm-wlm` and `munge` (`.ci/run` installs them and sets
//! TOWRIDE_REQUIRE_SLURM=1, so there it cannot pass without running); elsewhere it says
//! why it did not run. The stand-in test of `slurm.rs` covers machines without root.

use std::path::PathBuf;
use std::process::Command;
use std::time::{Duration, Instant};

use super::slurm::{same_tables, table};

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"));

/// The scratch cluster: its folder and config; `Drop` stops the daemons.
struct Cluster {
    dir: PathBuf,
    conf: PathBuf,
    socket: PathBuf,
}

impl Cluster {
    fn slurm(&self, prog: &str) -> Command {
        let mut c = Command::new(prog);
        c.env("SLURM_CONF", &self.conf);
        c
    }

    /// Writes the key and the config, starts the three daemons and waits for the node.
    fn start(dir: PathBuf) -> Result<Cluster, String> {
        let munge = dir.join("munge");
        for d in [&munge, &dir.join("state"), &dir.join("spool")] {
            std::fs::create_dir_all(d).map_err(|e| e.to_string())?;
        }
        let key: Vec<u8> = (0..1024u32)
            .map(|k| (k.wrapping_mul(2654435761) >> 13) as u8)
            .collect();
        let key_file = munge.join("munge.key");
        std::fs::write(&key_file, key).map_err(|e| e.to_string())?;
        run(Command::new("chmod").args(["700", munge.to_str().unwrap()]))?;
        run(Command::new("chmod").args(["400", key_file.to_str().unwrap()]))?;
        let socket = munge.join("munge.sock");
        // Ports from the process id, so that two test runs on one machine do not meet.
        let port = 20000 + (std::process::id() % 20000) as u16;
        let cpus = std::thread::available_parallelism().map_or(1, |n| n.get());
        let d = dir.display();
        let conf = dir.join("slurm.conf");
        let text = format!(
            "ClusterName=towride\nSlurmctldHost=localhost(127.0.0.1)\nSlurmUser=root\n\
             SlurmdUser=root\nSlurmctldPort={port}\nSlurmdPort={}\nAuthType=auth/munge\n\
             AuthInfo=socket={}\nCredType=cred/munge\nStateSaveLocation={d}/state\n\
             SlurmdSpoolDir={d}/spool\nSlurmctldPidFile={d}/slurmctld.pid\n\
             SlurmdPidFile={d}/slurmd.pid\nSlurmctldLogFile={d}/slurmctld.log\n\
             SlurmdLogFile={d}/slurmd.log\nProctrackType=proctrack/linuxproc\n\
             TaskPlugin=task/none\nSchedulerType=sched/builtin\nSelectType=select/cons_tres\n\
             SelectTypeParameters=CR_CPU\nReturnToService=2\nMpiDefault=none\n\
             JobCompType=jobcomp/none\nAccountingStorageType=accounting_storage/none\n\
             JobAcctGatherType=jobacct_gather/none\nMinJobAge=600\n\
             NodeName=localhost NodeAddr=127.0.0.1 CPUs={cpus} RealMemory=1000 State=UNKNOWN\n\
             PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP\n",
            port + 1,
            socket.display()
        );
        std::fs::write(&conf, text).map_err(|e| e.to_string())?;
        let c = Cluster { dir, conf, socket };
        let m = |f: &str| format!("--{f}={}", munge.join(f.replace('-', ".")).display());
        run(Command::new("munged").args([
            "--force".to_string(),
            format!("--socket={}", c.socket.display()),
            format!("--key-file={}", key_file.display()),
            m("log-file"),
            m("pid-file"),
            m("seed-file"),
        ]))?;
        run(c
            .slurm("slurmctld")
            .args(["-c", "-f", c.conf.to_str().unwrap()]))?;
        run(c
            .slurm("slurmd")
            .args(["-N", "localhost", "-f", c.conf.to_str().unwrap()]))?;
        let t0 = Instant::now();
        loop {
            let o = c.slurm("sinfo").args(["-h", "-o", "%T"]).output();
            let state = o.map_or(String::new(), |o| {
                String::from_utf8_lossy(&o.stdout).trim().to_string()
            });
            if state == "idle" {
                eprintln!(
                    "slurm: daemons up, node idle after {:.1} s",
                    t0.elapsed().as_secs_f64()
                );
                return Ok(c);
            }
            if t0.elapsed() > Duration::from_secs(30) {
                return Err(format!("node not idle after 30 s: {state:?}\n{}", c.logs()));
            }
            std::thread::sleep(Duration::from_millis(200));
        }
    }

    fn logs(&self) -> String {
        ["slurmctld.log", "slurmd.log", "munge/munged.log"]
            .iter()
            .map(|f| {
                let t = std::fs::read_to_string(self.dir.join(f)).unwrap_or_default();
                let tail: Vec<&str> = t.lines().rev().take(15).collect();
                format!(
                    "--- {f}\n{}",
                    tail.into_iter().rev().collect::<Vec<_>>().join("\n")
                )
            })
            .collect::<Vec<_>>()
            .join("\n")
    }
}

impl Drop for Cluster {
    fn drop(&mut self) {
        let _ = self.slurm("scontrol").arg("shutdown").output();
        for pid in ["slurmd.pid", "slurmctld.pid"] {
            if let Ok(p) = std::fs::read_to_string(self.dir.join(pid)) {
                let _ = Command::new("kill").arg(p.trim()).output();
            }
        }
        let _ = Command::new("munged")
            .args(["--stop", &format!("--socket={}", self.socket.display())])
            .output();
        eprintln!("slurm: daemons stopped");
    }
}

fn run(c: &mut Command) -> Result<(), String> {
    let o = c.output().map_err(|e| format!("{c:?}: {e}"))?;
    if o.status.success() {
        Ok(())
    } else {
        Err(format!("{c:?}: {}", String::from_utf8_lossy(&o.stderr)))
    }
}

/// Why this machine cannot run a real Slurm, if it cannot.
fn missing() -> Option<String> {
    let uid = Command::new("id").arg("-u").output().ok()?;
    if String::from_utf8_lossy(&uid.stdout).trim() != "0" {
        return Some("not root".into());
    }
    for prog in ["munged", "slurmctld", "slurmd", "sbatch", "squeue", "sinfo"] {
        let found = Command::new("sh")
            .args(["-c", &format!("command -v {prog}")])
            .output()
            .is_ok_and(|o| o.status.success());
        if !found {
            return Some(format!("{prog} not installed (Debian: slurm-wlm, munge)"));
        }
    }
    None
}

#[test]
fn a_real_slurm_runs_the_array_and_merges_to_the_unsharded_summary() {
    if let Some(why) = missing() {
        assert!(
            std::env::var_os("TOWRIDE_REQUIRE_SLURM").is_none(),
            "TOWRIDE_REQUIRE_SLURM is set but: {why}"
        );
        eprintln!("real-Slurm test not run: {why}");
        return;
    }
    let dir = std::env::temp_dir().join(format!("towride_slurm_real_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let cluster = Cluster::start(dir.join("cluster")).unwrap();
    let sweep = repo!("scenes/examples/pendulum_sweep.toml");
    let whole = dir.join("whole");
    let o = crate::towride(&[
        "sweep",
        sweep,
        "--out",
        whole.to_str().unwrap(),
        "--jobs",
        "1",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));

    let out = dir.join("array");
    let t0 = Instant::now();
    let o = cluster
        .slurm("bash")
        .arg(format!("{ROOT}/scripts/slurm/submit.sh"))
        .arg(sweep)
        .arg("3")
        .arg(&out)
        .current_dir(ROOT)
        .env("TOWRIDE_BIN", env!("CARGO_BIN_EXE_towride"))
        .output()
        .unwrap();
    let said = String::from_utf8_lossy(&o.stdout).to_string();
    assert!(
        o.status.success(),
        "{}{}",
        said,
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(said.starts_with("build none"), "{said}");
    eprintln!("slurm: {}", said.lines().next().unwrap_or(""));
    // squeue until nothing of ours is pending or running.
    loop {
        let q = cluster
            .slurm("squeue")
            .args(["-h", "-o", "%i %T"])
            .output()
            .unwrap();
        let q = String::from_utf8_lossy(&q.stdout).trim().to_string();
        if q.is_empty() {
            break;
        }
        assert!(
            t0.elapsed() < Duration::from_secs(300),
            "jobs still queued after 300 s:\n{q}\n{}",
            cluster.logs()
        );
        std::thread::sleep(Duration::from_millis(300));
    }
    eprintln!(
        "slurm: array and merge done in {:.1} s",
        t0.elapsed().as_secs_f64()
    );
    // Every job completed: 3 array tasks and the merge.
    let jobs = cluster
        .slurm("scontrol")
        .args(["show", "job", "-o"])
        .output()
        .unwrap();
    let jobs = String::from_utf8_lossy(&jobs.stdout).to_string();
    let states: Vec<&str> = jobs
        .lines()
        .filter_map(|l| l.split_whitespace().find(|w| w.starts_with("JobState=")))
        .collect();
    assert_eq!(states.len(), 4, "{jobs}");
    assert!(
        states.iter().all(|s| *s == "JobState=COMPLETED"),
        "{jobs}\n{}",
        cluster.logs()
    );
    for i in 0..3 {
        assert!(out.join(format!("summary_shard{i}of3.csv")).is_file());
    }
    let (a, b) = (
        table(&whole.join("summary.csv")),
        table(&out.join("summary.csv")),
    );
    assert_eq!(a.len(), 6);
    same_tables(&a, &b);
    drop(cluster);
    let _ = std::fs::remove_dir_all(&dir);
}
