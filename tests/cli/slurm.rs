//! The Slurm job-array workflow of `scripts/slurm/` run without Slurm: the shard step
//! once per array task (SLURM_ARRAY_TASK_ID set in turn), then the merge step; the merged
//! summary must equal the unsharded sweep's, number for number. `submit.sh` is run
//! against a stand-in `sbatch` that records its arguments, to check the chain
//! build -> array -> merge.

use std::path::{Path, PathBuf};
use std::process::Command;

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"));

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("towride_slurm_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs `scripts/slurm/<script>` with bash and the workflow's settings.
fn step(script: &str, out: &Path, shards: usize, task: Option<usize>) -> std::process::Output {
    let mut c = Command::new("bash");
    c.arg(format!("{ROOT}/scripts/slurm/{script}"))
        .current_dir(ROOT)
        .env("TOWRIDE_BIN", env!("CARGO_BIN_EXE_towride"))
        .env(
            "TOWRIDE_SWEEP",
            repo!("scenes/examples/pendulum_sweep.toml"),
        )
        .env("TOWRIDE_SHARDS", shards.to_string())
        .env("TOWRIDE_OUT", out)
        .env("TOWRIDE_SWEEP_ARGS", "--keep-histories");
    if let Some(i) = task {
        c.env("SLURM_ARRAY_TASK_ID", i.to_string());
    }
    c.output().expect("bash")
}

/// The table's rows by column name, numbers parsed; wall times left out.
pub(super) fn table(path: &Path) -> Vec<Vec<(String, String)>> {
    let mut r = csv::Reader::from_path(path).unwrap();
    let h: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    r.records()
        .map(|rec| {
            h.iter()
                .zip(rec.unwrap().iter())
                .filter(|(n, _)| !n.contains("wall time") && !n.contains("wall_time"))
                .map(|(n, v)| (n.clone(), v.to_string()))
                .collect()
        })
        .collect()
}

/// Two tables equal row by row, number for number.
pub(super) fn same_tables(a: &[Vec<(String, String)>], b: &[Vec<(String, String)>]) {
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(b) {
        assert_eq!(x.len(), y.len());
        for ((n1, v1), (n2, v2)) in x.iter().zip(y) {
            assert_eq!(n1, n2);
            match (v1.parse::<f64>(), v2.parse::<f64>()) {
                (Ok(p), Ok(q)) => assert_eq!(p, q, "{n1}"),
                _ => assert_eq!(v1, v2, "{n1}"),
            }
        }
    }
}

#[test]
fn the_slurm_array_run_locally_merges_to_the_unsharded_summary() {
    let whole = tmp("whole");
    let out = crate::towride(&[
        "sweep",
        repo!("scenes/examples/pendulum_sweep.toml"),
        "--out",
        whole.to_str().unwrap(),
        "--jobs",
        "1",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let arr = tmp("array");
    let n = 4; // 6 cases on 4 tasks: two tasks get two cases, two get one
    for i in 0..n {
        let o = step("shard.sbatch", &arr, n, Some(i));
        assert!(
            o.status.success(),
            "task {i}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(arr.join(format!("summary_shard{i}of{n}.csv")).is_file());
    }
    let o = step("merge.sbatch", &arr, n, None);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (a, b) = (
        table(&whole.join("summary.csv")),
        table(&arr.join("summary.csv")),
    );
    assert_eq!(a.len(), 6);
    same_tables(&a, &b);
    // The merged page links every case's report, kept by the tasks.
    let html = std::fs::read_to_string(arr.join("report.html")).unwrap();
    for k in 0..6 {
        assert!(arr.join(format!("cases/case_{k:04}/report.html")).is_file());
        assert!(html.contains(&format!("cases/case_{k:04}/report.html")));
    }
    // It opens in a browser and draws one chart per figure of the table.
    let figures = std::fs::read_to_string(arr.join("summary.csv"))
        .unwrap()
        .lines()
        .next()
        .unwrap()
        .split(',')
        .skip_while(|c| *c != "wall_time [s]")
        .count()
        - 2;
    let (_, ready) = crate::browser_dom(&arr.join("report.html"));
    assert_eq!(ready, Some(figures.to_string()));
    // A task outside the array is refused, not run as another shard.
    let o = step("shard.sbatch", &arr, n, Some(n));
    assert_eq!(o.status.code(), Some(2));
    // The merge refuses a missing shard.
    std::fs::remove_file(arr.join("summary_shard2of4.csv")).unwrap();
    assert!(!step("merge.sbatch", &arr, n, None).status.success());
}

#[test]
fn submit_chains_build_array_and_merge_by_dependency() {
    let dir = tmp("submit");
    // A stand-in sbatch: logs its arguments, answers job ids 101, 102, 103.
    let bin = dir.join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    let log = dir.join("sbatch.log");
    std::fs::write(
        bin.join("sbatch"),
        format!(
            "#!/usr/bin/env bash\necho \"$*\" >> {0}\necho $((100 + $(wc -l < {0})))\n",
            log.display()
        ),
    )
    .unwrap();
    Command::new("chmod")
        .arg("+x")
        .arg(bin.join("sbatch"))
        .status()
        .unwrap();
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let o = Command::new("bash")
        .arg(format!("{ROOT}/scripts/slurm/submit.sh"))
        .args(["scenes/hitch_variants.toml", "10"])
        .arg(dir.join("out"))
        .args(["--", "--keep-histories"])
        .current_dir(ROOT)
        .env("PATH", path)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let calls: Vec<String> = std::fs::read_to_string(&log)
        .unwrap()
        .lines()
        .map(String::from)
        .collect();
    assert_eq!(calls.len(), 3, "{calls:?}");
    assert!(calls[0].ends_with("build.sbatch"), "{}", calls[0]);
    assert!(
        calls[1].contains("--dependency=afterok:101"),
        "{}",
        calls[1]
    );
    assert!(calls[1].contains("--array=0-9"), "{}", calls[1]);
    assert!(calls[1].ends_with("shard.sbatch"), "{}", calls[1]);
    assert!(
        calls[2].contains("--dependency=afterok:102"),
        "{}",
        calls[2]
    );
    assert!(calls[2].ends_with("merge.sbatch"), "{}", calls[2]);
}
