//! `towride sweep rank`: one JSON document with its schema version, the three files, and
//! a bad parameter named with the summary's path.

const TABLE: &str = "\
case,hitch_variant,speed_km_h,status,wall_time [s],hitch_fx abs_peak [N],error
0,1,30,completed,0.5,100,
1,1,60,completed,0.5,140,
2,2,30,completed,0.5,80,
3,2,60,completed,0.5,100,
";

#[test]
fn rank_writes_its_files_and_one_json_document() {
    let dir = std::env::temp_dir().join(format!("towride_cli_rank_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("summary.csv");
    std::fs::write(&csv, TABLE).unwrap();
    let out = crate::towride(&["sweep", "rank", csv.to_str().unwrap(), "--json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(j["schema_version"], 1);
    assert_eq!(j["by"], "hitch_variant");
    assert_eq!(j["figures"][0]["best"], "2");
    assert_eq!(j["figures"][0]["entries"][1]["mean"], 90.0);
    for f in ["ranking.csv", "ranking.json", "ranking.png"] {
        assert!(dir.join(f).is_file(), "{f}");
    }
    let out = crate::towride(&["sweep", "rank", csv.to_str().unwrap(), "--by", "speed"]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("summary.csv") && err.contains("'speed'"),
        "{err}"
    );
}
