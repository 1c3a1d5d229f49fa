"""towride.sweep against the CLI's summary.json of the same sweep."""

import json
import subprocess

import towride

SWEEP = "scenes/examples/pendulum_sweep.toml"


def test_sweep_rows_equal_cli(cli, tmp_path):
    out = tmp_path / "cli"
    subprocess.run([cli, "sweep", SWEEP, "--out", str(out), "--json"], check=True, capture_output=True)
    want = json.loads((out / "summary.json").read_text())["rows"]
    got = towride.sweep(SWEEP).rows
    # 3 masses x 2 lengths (the sweep file).
    assert len(got) == len(want) == 6
    for g, w in zip(got, want):
        assert (g["index"], g["values"], g["status"]) == (w["index"], w["values"], w["status"])
        assert g["figures"] == w["figures"]


def test_sweep_out_writes_summary(tmp_path):
    res = towride.sweep(SWEEP, out=tmp_path / "s", jobs=1)
    assert (tmp_path / "s" / "summary.csv").exists()
    assert res["failed"] == 0 and res["cases"] == 6
