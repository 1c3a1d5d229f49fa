"""towride.run against the CLI's own files, run in the test."""

import json
import subprocess
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import towride

SCENE = "scenes/default.toml"


def test_default_scene_hitch_extremes_equal_cli(cli, tmp_path):
    out = tmp_path / "cli"
    subprocess.run([cli, "run", SCENE, "--out", str(out), "--json"], check=True, capture_output=True)
    want = json.loads((out / "summary.json").read_text())["channels"]["hitch_fx"]
    r = towride.run(SCENE)
    got = r.summary["channels"]["hitch_fx"]
    # To the last digit: the same doubles, not merely close ones.
    assert got["max"] == want["max"] and got["min"] == want["min"]
    assert float(r.channels["hitch_fx"].max()) == want["max"]
    assert float(r.channels["hitch_fx"].min()) == want["min"]
    # The samples equal outputs.csv's column (written with 10 significant digits).
    with open(out / "outputs.csv") as f:
        header = f.readline().strip().split(",")
    col = header.index("hitch_fx [N]")
    csv = np.loadtxt(out / "outputs.csv", delimiter=",", skiprows=1, usecols=col)
    np.testing.assert_allclose(r.channels["hitch_fx"], csv, rtol=1e-9, atol=0)


def test_channels_are_arrays_with_units():
    r = towride.run(SCENE)
    n = len(r.time)
    # 3 s at 1000 Hz, both ends included (scenes/default.toml [run]).
    assert n == 3001
    assert r.time[0] == 0.0 and r.time[-1] == pytest.approx(3.0)
    for name, v in r.channels.items():
        assert isinstance(v, np.ndarray) and v.dtype == np.float64 and v.shape == (n,), name
        assert name in r.units
    assert r.units["hitch_fx"] == "N"
    assert r.status == "completed"


def test_to_pandas_columns_carry_units():
    pd = pytest.importorskip("pandas")
    r = towride.run(SCENE)
    df = r.to_pandas()
    assert isinstance(df, pd.DataFrame)
    assert np.array_equal(df["hitch_fx [N]"].to_numpy(), r.channels["hitch_fx"])


def test_bad_set_raises_input_error_naming_the_argument():
    # As the CLI: a --set value the file refuses is blamed on the argument.
    with pytest.raises(towride.InputError) as e:
        towride.run(SCENE, set={"scenes/default.toml:run.speed_km_h": -5.0})
    err = e.value
    assert err.file == "command line" and err.line is None
    assert err.field == "--set scenes/default.toml:run.speed_km_h=-5.0"
    assert "must not be negative" in err.message


def test_bad_file_raises_input_error_with_file_line_field(tmp_path):
    text = open("scenes/examples/pendulum.toml").read()
    lines = text.splitlines()
    at = next(i for i, l in enumerate(lines) if l.startswith("mass_kg ="))
    lines[at] = "mass_kg = -1.0"
    bad = tmp_path / "pendulum.toml"
    bad.write_text("\n".join(lines) + "\n")
    with pytest.raises(towride.InputError) as e:
        towride.run(bad)
    err = e.value
    assert err.file == str(bad)
    assert err.line == at + 1
    assert err.field.endswith("mass_kg")


def test_malformed_set_raises_input_error():
    with pytest.raises(towride.InputError) as e:
        towride.run(SCENE, set=["no-equals-sign"])
    assert "FILE:PATH=VALUE" in str(e.value)


def test_out_writes_the_cli_files(tmp_path):
    r = towride.run(SCENE, out=tmp_path / "run")
    for f in ("outputs.csv", "summary.json", "report.html"):
        assert (tmp_path / "run" / f).exists(), f
    written = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert written["channels"]["hitch_fx"]["max"] == r.summary["channels"]["hitch_fx"]["max"]


def test_threads_run_in_parallel_and_agree():
    variants = [3, 8]
    t0 = time.perf_counter()
    one = towride.run(SCENE, set={"default.toml:scene.hitch_variant": variants[0]})
    single = time.perf_counter() - t0
    t0 = time.perf_counter()
    with ThreadPoolExecutor(2) as ex:
        both = list(ex.map(lambda v: towride.run(SCENE, set={"default.toml:scene.hitch_variant": v}), variants))
    pair = time.perf_counter() - t0
    assert np.array_equal(both[0].channels["hitch_fx"], one.channels["hitch_fx"])
    # Another variant, another force: the override reached the run.
    assert not np.array_equal(both[1].channels["hitch_fx"], one.channels["hitch_fx"])
    print(f"one run {single:.2f} s, two in two threads {pair:.2f} s")


def test_run_releases_the_gil():
    # A Python loop keeps turning while a run integrates in another thread: its longest
    # pause stays far below the run's wall time (with the GIL held it would span the run).
    import threading

    done = threading.Event()
    t = threading.Thread(target=lambda: (towride.run(SCENE), done.set()))
    t0 = time.perf_counter()
    last, gap = t0, 0.0
    t.start()
    while not done.is_set():
        now = time.perf_counter()
        gap, last = max(gap, now - last), now
    t.join()
    wall = time.perf_counter() - t0
    assert gap < 0.5 * wall, f"longest pause {gap:.2f} s of a {wall:.2f} s run"
