"""Files, processes and concurrency (issue 9): nothing lost, nothing left running, nothing silent.

These tests start real faultslip processes and send them real signals.
"""

import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from conftest import assert_clean_error
from faultslip.io.processes import children, is_alive

STUDY = """[study]
base = "san_andreas_1906.toml"
[sweep]
slip_rate = { logspace = ["1 mm/yr", "100 mm/yr", COUNT] }
zone_width = ["5 km", "13 mi", "30 km"]
"""


def _study(tmp_path, count=6, name="s.toml"):
    path = tmp_path / name
    path.write_text(STUDY.replace("COUNT", str(count)))
    return path


def _slow_study(tmp_path, count=300):
    """A study whose every cell is integrated (a polynomial kinetic law, DOP853 slip phases): ~30 ms per cell,
    slow enough to interrupt. (Cameron's law served until its exact map made its cells ~10 times faster.)"""
    path = tmp_path / "slow.toml"
    path.write_text('[study]\nbase = "lab_steel_dry_polynomial.toml"\n[sweep]\n'
                    f'platform_speed = {{ logspace = ["1e-5 m/s", "1e-4 m/s", {count}] }}\n')
    return path


def _faultslip(*args, **kwargs):
    return subprocess.Popen([sys.executable, "-m", "faultslip.cli", *map(str, args)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, **kwargs)


def _wait_for_progress(out, process, timeout=90):
    ledger = out.with_name(out.name + ".progress.json")
    deadline = time.time() + timeout
    while time.time() < deadline and process.poll() is None:
        try:
            if json.loads(ledger.read_text() or "{}").get("done"):
                return True
        except (OSError, ValueError):
            pass
        time.sleep(0.05)
    return False


needs_linux = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")


# --- processes -------------------------------------------------------------------------------

@needs_linux
def test_pool_workers_die_with_a_killed_parent(tmp_path):
    out = tmp_path / "big.nc"
    process = _faultslip("sweep", _slow_study(tmp_path), "-o", out, "--chunks", "10", "--workers", "2")
    assert _wait_for_progress(out, process), process.stderr.read() if process.poll() is not None else "no progress"
    workers = children(process.pid)
    assert workers, "the sweep runs a process pool"
    process.send_signal(signal.SIGKILL)
    process.wait()
    deadline = time.time() + 10
    while time.time() < deadline and any(is_alive(pid) for pid in workers):
        time.sleep(0.05)
    assert not any(is_alive(pid) for pid in workers), "pool workers outlived their parent"
    # the partial file left by kill -9 is resumed, never refused
    resumed = _faultslip("sweep", tmp_path / "slow.toml", "-o", out, "--chunks", "10", "--resume", "--json")
    stdout, stderr = resumed.communicate(timeout=300)
    assert resumed.returncode == 0, stderr
    assert json.loads(stdout)["resumed_blocks"] > 0


@needs_linux
def test_ctrl_c_to_the_process_group_gives_one_line_and_exit_130(tmp_path):
    out = tmp_path / "big.nc"
    # a terminal's Ctrl-C reaches a program started with SIGINT at its default; a shell's background job (as a
    # CI runner may start pytest) ignores SIGINT and its children inherit that, so the test sets it back
    process = _faultslip("sweep", _slow_study(tmp_path), "-o", out, "--chunks", "10", "--workers", "2",
                         start_new_session=True, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    assert _wait_for_progress(out, process)
    workers = children(process.pid)
    os.killpg(process.pid, signal.SIGINT)  # as a terminal's Ctrl-C: every process of the group
    stdout, stderr = process.communicate(timeout=30)  # no deadlock
    assert process.returncode == 130
    lines = [line for line in stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and "interrupted" in lines[0], stderr
    assert "Traceback" not in stderr
    assert not out.exists()
    time.sleep(0.5)
    assert not any(is_alive(pid) for pid in workers)


def test_a_truncated_partial_file_restarts_with_a_message(tmp_path, cli):
    out = tmp_path / "s.nc"
    study = _study(tmp_path)
    partial = out.with_name("s.nc.partial")
    partial.write_bytes(b"CDF\x01 truncated by kill -9")
    out.with_name("s.nc.progress.json").write_text('{"fingerprint": "x", "blocks": 1, "done": [0]')
    result = cli("sweep", study, "-o", out, "--resume", "--json")
    assert result.code == 0, result.err
    assert "starting over" in result.err and out.exists() and not partial.exists()


# --- locks and concurrency ---------------------------------------------------------------------

def test_a_second_writer_of_the_same_output_is_refused(tmp_path):
    out = tmp_path / "big.nc"
    study = _slow_study(tmp_path, 300)
    first = _faultslip("sweep", study, "-o", out, "--chunks", "10", "--workers", "1")
    assert _wait_for_progress(out, first)
    second = _faultslip("sweep", study, "-o", out, "--overwrite")
    _, stderr = second.communicate(timeout=120)
    assert second.returncode == 2
    assert f"pid {first.pid}" in stderr and "another faultslip run" in stderr and len(stderr.strip().splitlines()) == 1
    _, first_err = first.communicate(timeout=300)
    assert first.returncode == 0, first_err
    with xr.open_dataset(out) as result:  # the first run's results are all there
        assert result.sizes["platform_speed"] == 300 and np.isfinite(result["slip_per_event"].values).all()


def test_concurrent_fits_lose_nothing(tmp_path, monkeypatch):
    registry = tmp_path / "fits.json"
    data = Path(__file__).resolve().parents[3] / "configs" / "example_friction_data.csv"
    env = {**os.environ, "FAULTSLIP_REGISTRY": str(registry)}
    names = [f"gouge_{i}" for i in range(6)]
    runs = [_faultslip("fit", data, "--name", name, "--bootstrap", "20", env=env) for name in names]
    for run in runs:
        _, stderr = run.communicate(timeout=300)
        assert run.returncode == 0, stderr
    assert sorted(json.loads(registry.read_text())["fits"]) == names


def test_registry_names_damaged_and_shadowing_entries(tmp_path, monkeypatch):
    from faultslip.friction.materials import user_presets

    path = tmp_path / "fits.json"
    monkeypatch.setenv("FAULTSLIP_REGISTRY", str(path))
    good = {"mu_so": 0.7, "mu_m": 0.6, "b": 1.0, "d": 1.0}
    path.write_text(json.dumps({"faultslip_registry": 1, "fits": {
        "fine": good, "broken": {"mu_so": 0.7}, "glass_dry": good, "reversed": {**good, "mu_m": 0.9}}}))
    with pytest.warns(UserWarning) as caught:
        presets = user_presets()
    messages = " ".join(str(w.message) for w in caught)
    assert set(presets) == {"fine"}
    assert "'broken' is damaged" in messages and "'reversed' is damaged" in messages
    assert "'glass_dry' would shadow a bundled" in messages


def test_a_registry_entry_changed_after_saving_is_skipped_and_never_sealed_anew(tmp_path, monkeypatch):
    """Each entry carries its checksum: an edited entry is skipped, naming it, and a later save keeps it refused."""
    from faultslip.friction import registry
    from faultslip.friction.materials import user_presets

    path = tmp_path / "fits.json"
    monkeypatch.setenv("FAULTSLIP_REGISTRY", str(path))
    good = {"mu_so": 0.7, "mu_m": 0.6, "b": 1.0, "d": 1.0}
    registry.save_entry("gouge", good)
    registry.save_entry("edited", good)
    registry.save_entry("stripped", good)
    document = json.loads(path.read_text())
    assert document["faultslip_registry"] == 2 and all(len(e["checksum"]) == 64 for e in document["fits"].values())
    document["fits"]["edited"]["mu_m"] = 0.5  # a plausible value: only the checksum tells
    del document["fits"]["stripped"]["checksum"]
    path.write_text(json.dumps(document))
    with pytest.warns(UserWarning) as caught:
        presets = user_presets()
    messages = " ".join(str(w.message) for w in caught)
    assert set(presets) == {"gouge"} and presets["gouge"].rate_law.mu_m == 0.6
    assert "'edited' does not match the checksum" in messages and "'stripped' does not match" in messages
    registry.save_entry("later", good)  # read-modify-write: the damaged entries stay as they were, refused
    with pytest.warns(UserWarning) as caught:
        assert set(user_presets()) == {"gouge", "later"}
    messages = " ".join(str(w.message) for w in caught)
    assert "'edited' does not match the checksum" in messages and "'stripped' does not match" in messages


def test_an_older_registry_is_read_unchecked_with_one_warning(tmp_path, monkeypatch):
    from faultslip.friction import registry

    path = tmp_path / "fits.json"
    monkeypatch.setenv("FAULTSLIP_REGISTRY", str(path))
    good = {"mu_so": 0.7, "mu_m": 0.6, "b": 1.0, "d": 1.0}
    path.write_text(json.dumps({"faultslip_registry": 1, "fits": {"old_a": good, "old_b": good}}))
    with pytest.warns(UserWarning, match="written by an older faultslip, without checksums: its 2 entries"):
        assert set(registry.stored_entries()) == {"old_a", "old_b"}


# --- outputs, inputs and paths -----------------------------------------------------------------

@pytest.mark.parametrize("output, message", [
    ("missing_folder/out.nc", "does not exist"),
    (".", "is a folder"),
    ("out.txt", "must end in .nc"),
])
def test_outputs_are_checked_before_any_work(tmp_path, cli, monkeypatch, output, message):
    monkeypatch.chdir(tmp_path)
    assert_clean_error(cli("sweep", _study(tmp_path), "-o", output), message)


def test_existing_outputs_need_overwrite_and_an_input_is_never_an_output(tmp_path, cli):
    study = _study(tmp_path)
    out = tmp_path / "s.nc"
    assert cli("sweep", study, "-o", out).code == 0
    assert_clean_error(cli("sweep", study, "-o", out), "already exists", "--overwrite")
    assert cli("sweep", study, "-o", out, "--overwrite").code == 0
    before = out.read_bytes()
    assert_clean_error(cli("reproduce", out, "-o", out, "--overwrite"), "also an input")
    assert out.read_bytes() == before
    assert_clean_error(cli("simulate", "lab_glass_dry.toml", "--plot", tmp_path / "x.nc"), "must end in .png")


def test_map_cannot_overwrite_its_own_input(tmp_path, cli):
    raster = tmp_path / "raster.nc"
    grid = {"dims": ("lat", "lon"), "coords": {"lat": [37.0, 38.0], "lon": [-122.0, -121.0]}}
    xr.Dataset({name: xr.DataArray(np.full((2, 2), value), attrs={"units": unit}, **grid)
                for name, value, unit in (("shear_modulus", 0.25e6, "bar"), ("slip_rate", 20.0, "mm/yr"),
                                          ("zone_width", 13.0, "mi"), ("normal_stress", 385.0, "bar"))}).to_netcdf(raster)
    (tmp_path / "map.toml").write_text('[map]\n[raster]\nfile = "raster.nc"\n')
    before = raster.read_bytes()
    assert cli("map", tmp_path / "map.toml", "-o", tmp_path / "out.nc").code == 0
    assert_clean_error(cli("map", tmp_path / "map.toml", "-o", raster, "--overwrite"), "also an input")
    assert raster.read_bytes() == before


def test_paths_are_paths_and_bundled_scenes_are_named(tmp_path, cli, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert_clean_error(cli("run", "somewhere/san_andreas_1906.toml"), "does not exist")
    bundled = cli("run", "san_andreas_1906.toml", "--json")
    assert bundled.code == 0 and any("bundled scene san_andreas_1906.toml" in n for n in bundled.json["notes"])
    local = tmp_path / "san_andreas_1906.toml"  # a file of that name here wins, and is not called bundled
    local.write_text(Path(__file__).resolve().parents[3].joinpath("configs", "lab_glass_dry.toml").read_text())
    mine = cli("run", "san_andreas_1906.toml", "--json")
    assert mine.code == 0 and mine.json["title"].startswith("faultslip lab cycle")
    assert not any("bundled" in n for n in mine.json["notes"])


def test_a_bundled_study_and_map_are_named_as_a_scene_is(tmp_path, cli, monkeypatch):
    """'faultslip sweep study_rate_state.toml' runs anywhere, as faultslip.sweep() and 'faultslip run' take a
    bundled name; a name found nowhere is refused listing the bundled configs of its kind."""
    monkeypatch.chdir(tmp_path)
    swept = cli("sweep", "study_spring_slider.toml", "-o", tmp_path / "s.nc", "--estimate", "--json")
    assert swept.code == 0, swept.err
    assert cli("map", "san_andreas_map.toml", "--estimate", "--json").code == 0
    result = cli("sweep", "study_nowhere.toml", "-o", tmp_path / "s.nc")
    assert_clean_error(result, "study file 'study_nowhere.toml' does not exist here or among the bundled configs",
                       "the studies: study_asperity.toml")
    assert "san_andreas_1906.toml" not in result.err  # a scene is not a study
    assert_clean_error(cli("map", "map_nowhere.toml", "--estimate"), "the maps: california_fault_system.toml")
    assert_clean_error(cli("sweep", "somewhere/study_spring_slider.toml", "-o", tmp_path / "s.nc"), "does not exist")


# --- limits ------------------------------------------------------------------------------------

def test_a_huge_logspace_is_refused_before_allocating(tmp_path, cli):
    assert_clean_error(cli("sweep", _study(tmp_path, "10000000000"), "-o", tmp_path / "x.nc"),
                       "1e+10 values", "at most")


def test_a_two_week_grid_is_refused_with_its_estimate_and_the_override(tmp_path, cli):
    study = tmp_path / "huge.toml"
    study.write_text(STUDY.replace("COUNT", "1000000").replace('["5 km", "13 mi", "30 km"]',
                                                               '{ linspace = ["5 km", "30 km", 1000000] }'))  # 1e12 cells
    result = cli("sweep", study, "-o", tmp_path / "x.nc")
    assert_clean_error(result, "would need", "--allow-large")
    assert "days" in result.err


def test_workers_are_capped_with_a_note(tmp_path, cli):
    result = cli("sweep", _study(tmp_path), "-o", tmp_path / "s.nc", "--workers", "100000", "--json")
    assert result.code == 0, result.err
    assert "capped" in " ".join(result.json["notes"])
    assert_clean_error(cli("sweep", _study(tmp_path), "-o", tmp_path / "t.nc", "--workers", "0"), "at least 1")


def test_a_billion_cycle_simulation_is_refused(cli):
    result = cli("simulate", "lab_glass_dry.toml", "--cycles", "1000000000")
    assert_clean_error(result, "would need", "--allow-large")


# --- reproduce ---------------------------------------------------------------------------------

@pytest.fixture
def swept(tmp_path, cli):
    out = tmp_path / "s.nc"
    assert cli("sweep", _study(tmp_path), "-o", out).code == 0
    return out


def _tampered(path, change):
    with xr.open_dataset(path) as opened:
        data = opened.load()
    change(data)
    target = path.with_name("tampered.nc")
    data.to_netcdf(target)
    return target


@pytest.mark.parametrize("change", [
    lambda d: d["recurrence_period"].values.__setitem__((0, 0), 1.0),
    lambda d: d.__delitem__("stress_drop"),
    lambda d: d.__setitem__("extra", d["stress_drop"] * 2),
    lambda d: d["slip_per_event"].attrs.__setitem__("units", "ft"),
    lambda d: d.attrs.__setitem__("tolerance", 0.5),
    lambda d: d.attrs.__setitem__("history", "edited"),
], ids=["value", "deleted variable", "extra variable", "units", "global attribute", "run history"])
def test_reproduce_detects_every_kind_of_tampering(swept, cli, change):
    result = cli("reproduce", _tampered(swept, change), "--json")
    # the history is the run's own and is not compared: only the checksum written with the file tells
    assert result.code == 1 and result.json["matches"] is False and result.json["checksum"] == "differs"


def test_reproduce_matches_an_untouched_file(swept, cli):
    result = cli("reproduce", swept, "--json")
    assert result.code == 0 and result.json["matches"] is True and result.json["checksum"] == "matches"
    assert not result.json["missing"] and not result.json["extra"] and not result.json["attribute_differences"]


def _one_cell_changed(path, index):
    """``path`` with its cell ``index`` of the recurrence changed, sealed again: its checksum matches, so only a
    reproduction that runs that cell can tell."""
    from faultslip.io.netcdf import seal

    with xr.open_dataset(path) as opened:
        data = opened.load()
    data["recurrence_period"].values[index] *= 1.001
    target = path.with_name("one_cell.nc")
    data.to_netcdf(target)
    seal(target)
    return target


def test_a_spot_check_reruns_the_cells_it_draws_and_finds_a_changed_one_it_draws(swept, cli):
    """``reproduce --cells N`` runs again N cells drawn with ``--seed`` (a new draw, named in the output, without
    it), each as a sweep computes it, and compares them with the file's; the file's other cells and attributes are
    vouched for by its checksum. A cell changed and sealed again is found exactly when the draw holds it."""
    from faultslip.studies.streaming import reproduce

    result = cli("reproduce", swept, "--cells", "3", "--seed", "7", "--json")
    assert result.code == 0 and result.json["matches"] is True and result.json["checksum"] == "matches", result.err
    assert (result.json["cells"], result.json["of_cells"], result.json["sample_seed"]) == (3, 18, 7)
    sampled = result.json["sampled"]
    assert len({tuple(sorted(cell.items())) for cell in result.json["sampled_index"]}) == 3  # without replacement
    again = cli("reproduce", swept, "--cells", "3", "--seed", "7", "--json")
    assert again.json["sampled"] == sampled  # the same seed, the same cells
    drawn = cli("reproduce", swept, "--cells", "2", "--json")
    assert drawn.code == 0 and isinstance(drawn.json["sample_seed"], int)
    assert cli("reproduce", swept, "--cells", "2", "--seed", str(drawn.json["sample_seed"]),
               "--json").json["sampled"] == drawn.json["sampled"]
    text = cli("reproduce", swept, "--cells", "1", "--seed", "3")
    assert text.code == 0 and "1 of its 18 cells" in text.out and "--seed 3" in text.out
    changed = _one_cell_changed(swept, (0, 0))
    whole = cli("reproduce", changed, "--cells", "18", "--json")
    assert whole.code == 1 and whole.json["checksum"] == "matches" and whole.json["matches"] is False
    assert whole.json["differences"]["recurrence_period"] == pytest.approx(0.001 / 1.001, rel=1e-6)
    found = []
    for seed in range(8):
        spot = reproduce(changed, cells=6, seed=seed, workers=1)
        holds = {"slip_rate": 0, "zone_width": 0} in spot["sampled_index"]
        assert spot["matches"] is (not holds), (seed, spot["sampled"])
        found.append(holds)
    assert any(found) and not all(found)


@pytest.mark.parametrize("words, says", [
    (["--cells", "0"], "check 1 to 18"),
    (["--cells", "19"], "check 1 to 18"),
    (["--cells", "2", "--seed", "-1"], "0 or more"),
    (["--seed", "4"], "give --cells too"),
    (["--cells", "two"], "--cells"),
    (["--cells", "1", "--scheduler", "x"], "--scheduler"),
], ids=["none", "more than the study", "negative seed", "seed alone", "not a number", "no such scheduler"])
def test_a_spot_check_asked_wrongly_is_one_sentence(swept, cli, words, says):
    assert_clean_error(cli("reproduce", swept, *words), says)


def test_a_spot_check_keeps_no_file(swept, cli, tmp_path):
    kept = tmp_path / "kept.nc"
    assert_clean_error(cli("reproduce", swept, "--cells", "2", "-o", kept), "give one of them")
    assert not kept.exists()


def test_lock_refusal_names_the_holder(tmp_path):
    from faultslip.errors import InputError
    from faultslip.io.outputs import output_lock

    target = tmp_path / "x.nc"
    entered = threading.Event()
    release = threading.Event()

    def hold():
        with output_lock(target, "faultslip test"):
            entered.set()
            release.wait(10)

    holder = subprocess.Popen([sys.executable, "-c", (
        "import sys, time; from faultslip.io.outputs import output_lock\n"
        f"with output_lock({str(target)!r}, 'faultslip holder'):\n"
        "    print('held', flush=True); time.sleep(30)")], stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "held"
        with pytest.raises(InputError, match=rf"pid {holder.pid}, 'faultslip holder'"):
            with output_lock(target):
                pass
    finally:
        holder.kill()
        holder.wait()
    with output_lock(target):  # the kernel released the dead holder's lock
        pass


def test_the_time_budget_can_be_set_and_reproduce_checks_it(tmp_path, cli, monkeypatch, swept):
    monkeypatch.setenv("FAULTSLIP_TIME_BUDGET", "1e-9")
    assert_clean_error(cli("reproduce", swept), "would need", "--allow-large")
    assert cli("reproduce", swept, "--allow-large", "--json").code == 0


def test_an_absurdly_slow_platform_is_refused_not_a_traceback(tmp_path, cli):
    scene = tmp_path / "slow.toml"
    text = (Path(__file__).resolve().parents[3] / "configs" / "lab_steel_dry_time_of_stick.toml").read_text()
    scene.write_text(text.replace("platform_speed = \"8e-5 m/s\"", "platform_speed = \"1e-320 m/s\""))
    assert_clean_error(cli("simulate", scene, "--cycles", "3"), "platform speed")


def test_a_finished_pool_sweep_leaves_no_process_in_its_group(tmp_path):
    """Issue 43: processes were left in the default sweep's process group after it exited. The shared-memory
    segments' resource tracker outlived the sweep and, reparented to a PID 1 that reaps nothing (this
    micro-VM's init, a container's), stayed a zombie until that init's next sweep; it is now stopped and reaped
    at exit."""
    study = tmp_path / "pool.toml"
    study.write_text('[study]\nbase = "san_andreas_1906.toml"\n[sweep]\n'
                     'slip_rate = { logspace = ["5 mm/yr", "50 mm/yr", 2000] }\n'
                     'zone_width = { linspace = ["5 km", "30 km", 1000] }\n')
    process = subprocess.Popen([sys.executable, "-m", "faultslip.cli", "sweep", str(study), "-o",
                                str(tmp_path / "pool.nc"), "--workers", "2", "--json"], start_new_session=True,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    out, err = process.communicate(timeout=300)
    assert process.returncode == 0, err
    assert "pool" in json.loads(out)["executor"]  # the run this is about: a pool with shared memory
    # at once: the tracker is reaped before the sweep itself exits, so nothing of the group outlives it (left to
    # itself, the tracker exited after its parent, and this micro-VM's PID 1 reaped its zombie a second or so later)
    listing = subprocess.run(["ps", "-o", "pid=,stat=,cmd=", "-g", str(process.pid)], capture_output=True, text=True)
    left = [line for line in listing.stdout.splitlines() if line.strip()]
    assert left == [], left
