"""Estimates follow the machine (faultslip.io.machine): every family's cost model is scaled by the reference work's
time now over its time where the group's constants were anchored (benchmarks/machine_speed.py)."""

from __future__ import annotations

import json
import math
import multiprocessing
import os
import statistics
import tempfile
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import assert_clean_error, load_benchmark
from faultslip import models
from faultslip.errors import InputError
from faultslip.io import gate, machine
from faultslip.io.resources import read_bundled_table

from test_models import CONFIGS, SCENES

ROOT = Path(__file__).resolve().parents[3]


@pytest.mark.parametrize("family", sorted(SCENES))
@pytest.mark.parametrize("action", ["run", "simulate"])
def test_every_familys_estimate_follows_the_machine(family, action, monkeypatch):
    """A machine twice as slow doubles every family's estimated CPU time, run and simulation, through the contract
    (models.estimate), and leaves its memory and disk alone."""
    scene = CONFIGS / SCENES[family]
    monkeypatch.setenv(machine.ENVIRONMENT, "1")
    anchored = models.estimate(scene, action)
    monkeypatch.setenv(machine.ENVIRONMENT, "2")
    slower = models.estimate(scene, action)
    # the cost model's seconds, without the imports the first estimate measured (this machine's CPU already)
    modelled, modelled_slower = anchored.modelled_seconds, slower.modelled_seconds
    assert modelled > 0
    assert modelled_slower == pytest.approx(2 * modelled, rel=1e-12)
    assert (slower.memory, slower.disk) == (anchored.memory, anchored.disk)


def test_the_factor_is_the_reference_work_now_over_each_groups_anchor(monkeypatch):
    """Unset, the factor is the probe's time now over the group's anchored time; the probe is measured once a
    process (and again after its lifetime), on this thread."""
    monkeypatch.delenv(machine.ENVIRONMENT, raising=False)
    anchors = machine.references()
    for group, seconds in anchors.items():
        monkeypatch.setattr(machine, "reference_now", lambda seconds=seconds: 3.0 * seconds)
        assert machine.factor(group) == pytest.approx(3.0, rel=1e-12)
    assert set(anchors) == set(machine.GROUPS)
    with pytest.raises(ValueError, match="unknown cost group"):
        machine.factor("fault_4d")


def test_the_probe_is_measured_once_and_says_what_it_scaled(monkeypatch):
    monkeypatch.delenv(machine.ENVIRONMENT, raising=False)
    monkeypatch.setattr(machine, "_probe", {})
    calls = []
    monkeypatch.setattr(machine, "probe_seconds", lambda: calls.append(1) or 1e-3)
    assert machine.reference_now() == machine.reference_now() == 1e-3
    assert len(calls) == 1
    assert "reference work took 1 ms" in machine.describe()
    assert machine.on_this_machine(0.0, "families") == 0.0
    # the work itself: a positive, finite CPU time
    seconds = machine.reference_work(size=256, rounds=2)
    assert math.isfinite(seconds) and seconds >= 0.0


def test_an_estimate_says_how_it_was_scaled(monkeypatch):
    monkeypatch.setenv(machine.ENVIRONMENT, "1.5")
    report = models.estimate(CONFIGS / "fault_2d_small.toml").report()
    assert any("scaled by 1.5" in note for note in report.notes)


@pytest.mark.parametrize("text", ["fast", "0", "-1", "nan", "inf", "1e9", ""])
def test_a_bad_factor_is_one_sentence(text, monkeypatch, cli):
    monkeypatch.setenv(machine.ENVIRONMENT, text)
    with pytest.raises(InputError, match="FAULTSLIP_MACHINE_FACTOR"):
        machine.factor("families")
    assert_clean_error(cli("run", CONFIGS / "fault_2d_small.toml", "--estimate"), "FAULTSLIP_MACHINE_FACTOR")


def test_the_reference_is_what_its_benchmark_measured():
    """data/machine_reference.json is benchmarks/results/machine_speed.json's runs, recomputed: each group's
    reference is the median probe times the median of CPU then / now over its runs; and each run's "then" is what
    its fit's results file holds as it stands (a refit without rerunning machine_speed.py fails here)."""
    speed = load_benchmark("machine_speed")
    shipped = read_bundled_table(machine.REFERENCE_FILE, "reference", "benchmarks/machine_speed.py")["groups"]
    record = json.loads((ROOT / "benchmarks" / "results" / "machine_speed.json").read_text(encoding="utf-8"))
    for group in machine.GROUPS:
        runs = record["groups"][group]["runs"]
        assert len(runs) >= 3, group
        ratio = statistics.median(run["then"] / run["now"] for run in runs)
        probe = statistics.median(record["groups"][group]["probe_now_seconds"])
        assert shipped[group]["reference_work_seconds"] == pytest.approx(probe * ratio, rel=1e-12)
        fitted = speed.recorded(group)
        for run in runs:
            assert run["then"] == pytest.approx(fitted[run["run"]], rel=1e-12), (group, run["run"])


def test_the_families_cost_table_is_its_benchmarks_fit_of_the_recorded_cases():
    """data/family_costs.json is benchmarks/family_costs.py's fit of the cases benchmarks/results/family_costs.json
    records (least squares in the log of estimate over CPU), not numbers typed or left from another fit, each entry
    measured or borrowed from a measured one; and its cases, fitted and held out, are estimated within 2x of their
    CPU, 95 % of them at least, and every one within 3x. In seconds, the fit had set a rough-surface Radau entry's
    overhead at 0.37 s, its cheapest runs estimated at 2.9x their CPU; a rough-surface run whose refinement check
    tightens its rtol costs up to three times its siblings, which no estimate made before the run can know."""
    costs = load_benchmark("family_costs")
    shipped = read_bundled_table("family_costs.json", "the families' cost models", "benchmarks/family_costs.py")
    rows = json.loads((ROOT / "benchmarks" / "results" / "family_costs.json").read_text(encoding="utf-8"))["rows"]
    for family, entries in shipped["families"].items():
        for entry, fitted in entries.items():
            if fitted.get("borrowed_from"):
                assert entries[fitted["borrowed_from"]]["fitted_on"], (family, entry)
                continue
            cases = [row for row in rows if (row["family"], row["entry"]) == (family, entry) and not row["held_out"]]
            assert sorted(row["case"] for row in cases) == sorted(fitted["fitted_on"]), (family, entry)
            # a settle's row holds the work its estimate models; the fit took the work measured
            refit = costs.fit([{**row, "units": row.get("units_measured", row["units"])} for row in cases])
            for key in ("overhead", "seconds_per_unit"):
                assert fitted[key] == pytest.approx(refit[key], rel=1e-6, abs=1e-12), (family, entry, key)
    ratios = [row["ratio"] for row in rows]
    assert sum(0.5 <= ratio <= 2.0 for ratio in ratios) >= 0.95 * len(ratios)
    for row in rows:
        assert 1 / 3 <= row["ratio"] <= 3.0, row["case"]


# --- the machine speed record: the median of many processes' probes, not one moment's --------------------------

@pytest.fixture
def record(tmp_path, monkeypatch):
    """A fresh record at a temporary path, the factor unfixed and this process's probe forgotten."""
    path = tmp_path / "cache" / "machine_speed.json"
    monkeypatch.delenv(machine.ENVIRONMENT, raising=False)
    monkeypatch.setenv(machine.RECORD_ENVIRONMENT, str(path))
    monkeypatch.setattr(machine, "_probe", {})
    return path


def _sealed_record(machines: dict) -> str:
    document = {"faultslip_machine_record": machine.RECORD_VERSION, "machines": machines}
    return json.dumps(document | {"checksum": gate.json_checksum(document)})


def test_the_record_gives_the_median_of_this_machines_readings(record, monkeypatch):
    """Each process adds its probe; the estimate takes the median of this kind of machine's kept readings, so one
    slow moment (3 ms among 1 ms readings) moves nothing, and the report says how many readings it took."""
    readings = [1e-3, 1.1e-3, 3e-3, 0.9e-3, 1.05e-3]
    for count, reading in enumerate(readings, start=1):
        median, kept, source = machine.recorded_median(reading)
        assert (median, kept, source) == (statistics.median(readings[:count]), count, str(record))
    stored = machine.read_record(record)
    assert [item[1] for item in stored[machine.machine_kind()]] == readings
    monkeypatch.setattr(machine, "probe_seconds", lambda: 1e-3)
    median = statistics.median(readings + [1e-3])
    assert machine.reference_now() == pytest.approx(median ** (1 - machine.PROBE_WEIGHT) * 1e-3 ** machine.PROBE_WEIGHT,
                                                    rel=1e-12)  # this process's probe keeps its weight beside it
    assert machine.speed_reading() == {"reading": 1e-3, "median": median, "readings": 6, "record": str(record),
                                       "seconds": machine.reference_now()}
    assert "the median of 6 readings of this kind of machine" in machine.describe()
    assert machine.factor("families") == pytest.approx(machine.reference_now() / machine.references()["families"])


def test_the_record_keeps_the_last_readings_the_recent_machines_and_drops_old_ones(record, monkeypatch):
    now = 2.0e9
    monkeypatch.setattr(machine.time, "time", lambda: now)
    kind = machine.machine_kind()
    old = [[now - machine.RECORD_MAX_AGE - 1.0, 5e-3]] * 3  # a month and more ago: another state of the machine
    others = {f"machine {i} x4": [[now - 10.0 * (i + 1), 2e-3]] for i in range(machine.RECORD_MACHINES - 1)}
    record.parent.mkdir(parents=True)
    record.write_text(_sealed_record({kind: old, **others}), encoding="utf-8")
    assert machine.recorded_median(1e-3) == (1e-3, 1, str(record))  # the old readings are not taken
    stored = machine.read_record(record)
    assert len(stored) == machine.RECORD_MACHINES and stored[kind] == [[now, 1e-3]]
    with monkeypatch.context() as patch:  # a seventeenth kind of machine: the least recently read is dropped
        patch.setattr(machine, "machine_kind", lambda: "another processor x64")
        machine.recorded_median(4e-3)
    stored = machine.read_record(record)
    assert len(stored) == machine.RECORD_MACHINES and "another processor x64" in stored
    assert f"machine {machine.RECORD_MACHINES - 2} x4" not in stored and kind in stored
    for i in range(2 * machine.RECORD_READINGS):
        median, kept, _ = machine.recorded_median(1e-3 * (1 + i))
    assert kept == machine.RECORD_READINGS
    last = [1e-3 * (1 + i) for i in range(machine.RECORD_READINGS, 2 * machine.RECORD_READINGS)]
    assert median == statistics.median(last)


@settings(max_examples=25)
@given(st.lists(st.floats(min_value=1e-5, max_value=0.5), min_size=1, max_size=45))
def test_the_record_round_trips_and_its_median_is_the_last_readings(readings):
    """Any run of readings: each answer is the median of the last RECORD_READINGS (its own included), and the file
    read back matches the checksum written with it (floats exact through JSON)."""
    with tempfile.TemporaryDirectory() as folder, pytest.MonkeyPatch.context() as patch:
        path = Path(folder) / "record.json"
        patch.setenv(machine.RECORD_ENVIRONMENT, str(path))
        for count, reading in enumerate(readings, start=1):
            median, kept, _ = machine.recorded_median(reading)
            window = readings[max(0, count - machine.RECORD_READINGS):count]
            assert (median, kept) == (statistics.median(window), len(window))
        assert [item[1] for item in machine.read_record(path)[machine.machine_kind()]] == window


def _edited(text: str) -> str:
    document = json.loads(text)
    document["machines"][machine.machine_kind()][0][1] *= 10  # a hand making this machine look slower
    return json.dumps(document)


def _foreign_values(text: str) -> str:
    return _sealed_record({machine.machine_kind(): [[1.0, 5.0]]})  # sealed, but a reading no probe gives


@pytest.mark.parametrize("damage, words", [
    (_edited, "does not match the checksum"),
    (lambda text: text[: len(text) // 2], "JSON"),
    (lambda text: "[1, 2]", "not a record this faultslip writes"),
    (_foreign_values, "holds readings no faultslip writes"),
    (lambda text: " " * (machine.RECORD_BYTES + 1), "the limit for such a file"),
])
def test_a_damaged_record_is_neither_used_nor_changed(record, damage, words):
    """An edited, cut, foreign or oversized record: the estimate goes on with this process's probe alone, one
    warning says why, and the file keeps every byte (the user's to look at or remove)."""
    machine.recorded_median(2e-3)
    text = damage(record.read_text(encoding="utf-8"))
    record.write_text(text, encoding="utf-8")
    with pytest.warns(UserWarning, match=words) as caught:
        assert machine.recorded_median(1e-3) == (1e-3, 1, "the machine speed record was not usable")
    assert len(caught) == 1 and "this process's probe of the machine alone" in str(caught[0].message)
    assert record.read_text(encoding="utf-8") == text


@pytest.mark.parametrize("planted", ["link", "fifo", "folder"])
def test_a_record_path_that_is_not_a_file_is_never_followed(record, planted, tmp_path):
    record.parent.mkdir(parents=True)
    victim = tmp_path / "victim.json"
    victim.write_text("precious", encoding="utf-8")
    if planted == "link":
        record.symlink_to(victim)
    elif planted == "fifo":
        os.mkfifo(record)
    else:
        record.mkdir()
    with pytest.warns(UserWarning, match="machine speed record"):
        assert machine.recorded_median(1e-3)[1] == 1
    assert victim.read_text(encoding="utf-8") == "precious"
    assert record.is_symlink() if planted == "link" else record.exists()


def test_no_record_is_kept_where_it_is_off(record, monkeypatch):
    monkeypatch.setenv(machine.RECORD_ENVIRONMENT, "off")
    assert machine.recorded_median(1e-3) == (1e-3, 1, "no record kept (FAULTSLIP_MACHINE_RECORD is off)")
    assert machine.record_path() is None and not record.parent.exists()
    monkeypatch.delenv(machine.RECORD_ENVIRONMENT)
    monkeypatch.setenv("XDG_CACHE_HOME", str(record.parent))
    assert machine.record_path() == record.parent / "faultslip" / "machine_speed.json"


def _add_readings(path: str, readings: list) -> None:
    os.environ[machine.RECORD_ENVIRONMENT] = path
    for reading in readings:
        machine.recorded_median(reading)


def test_concurrent_processes_lose_no_reading(record):
    """Processes that probe at once (a pool's workers) each land their readings: the record is updated under its
    lock, read and written again."""
    record.parent.mkdir(parents=True)
    context = multiprocessing.get_context("fork")
    workers = [context.Process(target=_add_readings, args=(str(record), [1e-3 * (1 + w + 0.1 * i) for i in range(3)]))
               for w in range(6)]
    for worker in workers:
        worker.start()
    for worker in workers:
        worker.join(60)
    assert [worker.exitcode for worker in workers] == [0] * 6
    readings = sorted(item[1] for item in machine.read_record(record)[machine.machine_kind()])
    assert readings == sorted(1e-3 * (1 + w + 0.1 * i) for w in range(6) for i in range(3))


def test_an_estimate_with_a_damaged_record_runs_and_says_so(record, cli):
    """Through the CLI: exit 0, the estimate from this process's probe alone, one warning line naming the
    record, and the record untouched."""
    record.parent.mkdir(parents=True)
    record.write_text("not json", encoding="utf-8")
    result = cli("run", CONFIGS / "fault_2d_small.toml", "--estimate", "--json")
    assert result.code == 0, result.err
    assert [line for line in result.err.splitlines() if line] == [line for line in result.err.splitlines()
                                                                  if line.startswith("faultslip: warning:")]
    assert len(result.err.strip().splitlines()) == 1 and "machine speed record" in result.err
    notes = " ".join(json.loads(result.out)["notes"])
    assert "this process's probe alone" in notes
    assert record.read_text(encoding="utf-8") == "not json"


def test_the_record_and_the_probes_weight_follow_the_runs_better_than_one_probe():
    """benchmarks/results/machine_record.json and machine_record_held_out.json: the same runs' estimates made again
    with the record's median alone, with the probe alone, and with the two weighted as faultslip ships
    (PROBE_WEIGHT). Each summary is the benchmark's own of its rows; PROBE_WEIGHT is the first run's least-squares
    weight, to a third; and on the second run, which never set it, the shipped weighting spreads the estimates less
    (sd in ln) and over a narrower range than either alone, every one within 2x."""
    bench = load_benchmark("machine_record")
    assert bench.WEIGHTS == {"with_record": 0.0, "blended": machine.PROBE_WEIGHT, "probe_alone": 1.0}
    results = {}
    for path in (bench.OUT, bench.HELD_OUT):
        result = json.loads(path.read_text(encoding="utf-8"))
        assert result["summary"] == bench.summarise(result["rows"])
        assert result["summary"]["processes"] >= 60
        results[path] = result["summary"]
    assert abs(results[bench.OUT]["probe_weight_fit"] - machine.PROBE_WEIGHT) <= 0.05
    held_out = results[bench.HELD_OUT]
    blended, record, alone = held_out["blended"], held_out["with_record"], held_out["probe_alone"]
    assert blended["sd_ln"] < min(record["sd_ln"], alone["sd_ln"])
    assert blended["max_over_min"] <= min(record["max_over_min"], alone["max_over_min"])
    assert blended["within_2x"] == held_out["processes"]
    row = json.loads(bench.HELD_OUT.read_text(encoding="utf-8"))["rows"][-1]  # one estimate made again by hand
    factor = (row["median"] / row["anchor"]) ** (1 - machine.PROBE_WEIGHT) * (row["reading"] / row["anchor"]) ** (
        machine.PROBE_WEIGHT)
    assert bench.ratio(row, machine.PROBE_WEIGHT) == pytest.approx(
        (row["import_seconds"] + row["anchored_seconds"] * factor) / row["cpu_time"], rel=1e-12)
