"""Units at the boundary: parsing, the Julian year, and rejected inputs."""

import json
import math
import os
import re

import numpy as np
import pint
import pytest

from faultslip.errors import InputError
from faultslip.units import JULIAN_YEAR, STANDARD_GRAVITY, to_si, units


def test_year_is_julian_everywhere():
    assert JULIAN_YEAR == 365.25 * 86400
    assert units.Quantity(1, "year").to("s").magnitude == JULIAN_YEAR
    assert units.Quantity(1, "yr").to("day").magnitude == 365.25
    # seed 003 used 365 d: 0.068 % shorter
    assert math.isclose(JULIAN_YEAR / (365 * 86400) - 1, 0.000685, rel_tol=1e-2)


@pytest.mark.parametrize(
    "text, kind, expected",
    [
        ("13 mi", "length", 13 * 1609.344),
        ("2 in/yr", "speed", 2 * 0.0254 / JULIAN_YEAR),
        ("0.25e6 bar", "pressure", 0.25e11),
        ("250 bar", "pressure", 2.5e7),
        ("24 mm/yr", "speed", 0.024 / JULIAN_YEAR),
        ("1.94e4 lbf/in", "stiffness", 1.94e4 * 4.4482216152605 / 0.0254),
        ("5e-11 1/s", "rate", 5e-11),
        ("2700 kg/m^3", "density", 2700.0),
        ("3.3 km/s", "speed", 3300.0),
    ],
)
def test_examples_from_the_issue_parse_to_si(text, kind, expected):
    assert to_si(text, kind, "x") == pytest.approx(expected, rel=1e-13)


def test_pint_quantity_and_foreign_registry_are_accepted():
    assert to_si(units.Quantity(13, "mi"), "length", "D") == pytest.approx(20921.472)
    other = pint.UnitRegistry()
    assert to_si(other.Quantity(2, "in/yr"), "speed", "V") == pytest.approx(2 * 0.0254 / JULIAN_YEAR)


def test_array_quantities_convert_elementwise():
    out = to_si(units.Quantity(np.array([1.0, 2.0]), "bar"), "pressure", "p")
    np.testing.assert_allclose(out, [1e5, 2e5])


def test_wrong_dimension_names_the_input_and_the_kind():
    with pytest.raises(InputError, match=r"slip rate must be a speed .*got 2 bar"):
        to_si("2 bar", "speed", "slip rate")


def test_bare_number_is_rejected_unless_a_default_unit_is_documented():
    with pytest.raises(InputError, match="elastic-zone width must be a length with units"):
        to_si(13, "length", "elastic-zone width")
    assert to_si(13, "length", "D", default_unit="mi") == pytest.approx(20921.472)
    assert to_si("0.65", "dimensionless", "mu_so") == 0.65


@pytest.mark.parametrize("given, said", [(13, "the bare number 13"), ([1, 2], "a value without units, [1, 2]"),
                                         (np.float32(2.5), "the bare number")])
def test_a_value_without_units_is_named_as_what_it_is(given, said):
    with pytest.raises(InputError, match=re.escape(said)):
        to_si(given, "length", "elastic-zone width")


def test_dimensionless_rejects_units():
    with pytest.raises(InputError, match="mu_so must be a dimensionless number"):
        to_si("0.65 bar", "dimensionless", "mu_so")


@pytest.mark.parametrize(
    "bad, kind", [("nan", "dimensionless"), ("nan bar", "pressure"), (float("nan"), "dimensionless"), ("inf m", "length")]
)
def test_nan_and_infinity_are_rejected(bad, kind):
    with pytest.raises(InputError, match="finite"):
        to_si(bad, kind, "value")


def test_unknown_unit_is_a_clear_error():
    with pytest.raises(InputError, match="unknown unit 'furlongz' in '13 furlongz'"):
        to_si("13 furlongz", "length", "D")


def test_load_in_pounds_mass_is_read_as_a_weight():
    assert to_si("225.8 lb", "force", "W") == pytest.approx(225.8 * 0.45359237 * STANDARD_GRAVITY)
    assert to_si("225.8 lb", "force", "W") == pytest.approx(to_si("225.8 lbf", "force", "W"), rel=1e-12)
    with pytest.raises(InputError):
        to_si("2 kg", "length", "D")  # the gravitational reading applies to forces only


# --- pint on demand, its answers memoised (issue 32's start-up target) ---------------------------

def _fresh_memo(monkeypatch, folder):
    import faultslip.units as fu

    monkeypatch.setenv("XDG_CACHE_HOME", str(folder))
    monkeypatch.setattr(fu, "_MEMO", None)
    fu._unit_factor.cache_clear()
    fu._conversion.cache_clear()
    return fu


@pytest.mark.parametrize("text, kind", [("13 mi", "length"), ("2 in/yr", "speed"), ("0.25e6 bar", "pressure"),
                                        ("225.8 lb", "force"), ("125 rad/s", "frequency"), ("1e-3 1/um", "inverse_length"),
                                        ("3.8 MPa*s/m", "stress_damping"), ("100 yr", "time")])
def test_the_memo_gives_exactly_what_pint_gives(monkeypatch, tmp_path, text, kind):
    fu = _fresh_memo(monkeypatch, tmp_path)
    first = fu.to_si(text, kind, "x")  # asks pint and remembers
    fu = _fresh_memo(monkeypatch, tmp_path)
    again = fu.to_si(text, kind, "x")  # read from the file
    assert again == first
    stored = json.loads(fu._memo_path().read_text())
    for key, (factor, note) in stored["factors"].items():
        kind_, unit = key.split("\x1f", 1)
        assert fu._pint_unit_factor(unit, kind_) == (factor, note)


def test_a_stale_or_damaged_memo_is_ignored_and_rewritten(monkeypatch, tmp_path):
    fu = _fresh_memo(monkeypatch, tmp_path)
    path = fu._memo_path()
    path.parent.mkdir(parents=True)
    path.write_text(json.dumps({"pint": "another pint", "factors": {"length\x1fmi": [1.0, ""]}}))
    assert fu.to_si("1 mi", "length", "x") == 1609.344
    fu = _fresh_memo(monkeypatch, tmp_path)
    path.write_text("{not json")
    assert fu.to_si("1 mi", "length", "x") == 1609.344
    assert json.loads(path.read_text())["factors"]["length\x1fmi"] == [1609.344, ""]


def test_each_environment_keeps_its_own_memo(monkeypatch, tmp_path):
    """Two virtual environments sharing a home folder (CI's and a developer's) kept invalidating one memo
    file, and every first command paid pint's import again: the memo's name now carries the environment."""
    fu = _fresh_memo(monkeypatch, tmp_path)
    here = fu._memo_path()
    assert here.parent == tmp_path / "faultslip"
    monkeypatch.setattr(fu.sys, "prefix", "/another/venv")
    fu._environment_key.cache_clear()
    try:
        assert fu._memo_path() != here
    finally:
        fu._environment_key.cache_clear()


def test_an_unwritable_cache_costs_only_the_lookup(monkeypatch, tmp_path):
    blocked = tmp_path / "file"
    blocked.write_text("a file where the folder would be")
    fu = _fresh_memo(monkeypatch, blocked)
    assert fu.to_si("13 mi", "length", "x") == pytest.approx(20921.472)
    with pytest.raises(InputError, match="unknown unit"):
        fu.to_si("13 zorkmids", "length", "x")


def test_a_closed_form_command_with_known_units_starts_without_pint(tmp_path):
    import subprocess
    import sys

    code = ("import sys; from faultslip.cli.main import main; "
            "main(['fault', '--lithology', 'granodiorite', '--zone-width', '13 mi', '--shear-stress', '250 bar', "
            "'--slip-rate', '2 in/yr', '--json']); print('pint' in sys.modules, 'dask' in sys.modules, file=sys.stderr)")
    env = dict(os.environ, XDG_CACHE_HOME=str(tmp_path))
    runs = [subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=120)
            for _ in range(2)]
    assert all(run.returncode == 0 for run in runs), runs[0].stderr
    assert runs[0].stdout == runs[1].stdout  # the memo changes nothing in the answer
    assert runs[0].stderr.split()[-2:] == ["True", "False"]  # the first run asked pint, without dask
    assert runs[1].stderr.split()[-2:] == ["False", "False"]  # the second did not need it


def test_pint_loaded_without_its_dask_probe_leaves_dask_importable():
    import subprocess
    import sys

    code = ("import faultslip.units as fu; fu.PINT_WITHOUT_DASK = True; fu.registry(); import pint.compat, dask.array; "
            "print(pint.compat.HAS_DASK, dask.array.ones(3).sum().compute())")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["False", "3.0"]


def test_a_memo_with_one_changed_digit_is_not_trusted(monkeypatch, tmp_path):
    """A factor edited in the memo (its digest no longer matching) is dropped and asked of pint again: one changed
    digit used to shift every chain magnitude by 0.67."""
    fu = _fresh_memo(monkeypatch, tmp_path)
    assert fu.to_si("1 km", "length", "x") == 1000.0
    path = fu._memo_path()
    stored = json.loads(path.read_text())
    stored["factors"]["length\x1fkm"] = [10000.0, ""]
    path.write_text(json.dumps(stored))
    fu = _fresh_memo(monkeypatch, tmp_path)
    assert fu.to_si("1 km", "length", "x") == 1000.0
    assert json.loads(path.read_text())["factors"]["length\x1fkm"] == [1000.0, ""]  # rewritten from pint


def test_processes_that_learn_units_at_once_keep_each_others_entries(monkeypatch, tmp_path):
    """Each process read the memo once and wrote back its own reading, so of processes learning units at once the
    last writer dropped the others' entries (a test run's workers did: a later command then loaded pint). Each write
    now merges, under a lock, what is on disk: eight processes, each learning its own unit, leave all eight."""
    import subprocess
    import sys

    fu = _fresh_memo(monkeypatch, tmp_path)
    units = ["1 km", "1 mi", "1 ft", "1 in", "1 yd", "1 nmi", "1 mm", "1 um"]
    code = ("import sys, time; import faultslip.units as fu; fu._memo(); time.sleep(0.5); "
            "fu.to_si(sys.argv[1], 'length', 'x')")
    environment = {**__import__("os").environ, "XDG_CACHE_HOME": str(tmp_path)}
    running = [subprocess.Popen([sys.executable, "-c", code, text], env=environment) for text in units]
    assert all(process.wait(timeout=120) == 0 for process in running)
    stored = json.loads(fu._memo_path().read_text())
    assert {f"length\x1f{text.split()[1]}" for text in units} <= set(stored["factors"])
    assert stored["checksum"] == fu._memo_checksum(stored["pint"], stored["factors"])


@pytest.mark.parametrize("planted", ["symlink", "fifo"])
def test_a_memo_path_that_is_a_link_or_a_fifo_is_not_read(monkeypatch, tmp_path, planted):
    """The memo is opened without following a link and without waiting on a FIFO: a link to another file's
    contents is never trusted, a FIFO never hangs the first unit a command reads; pint answers instead."""
    import os

    fu = _fresh_memo(monkeypatch, tmp_path)
    path = fu._memo_path()
    path.parent.mkdir(parents=True)
    if planted == "symlink":
        elsewhere = tmp_path / "elsewhere.json"
        elsewhere.write_text(json.dumps({"pint": fu._pint_fingerprint(), "factors": {"length\x1fmi": [2.0, ""]}}))
        path.symlink_to(elsewhere)
    else:
        os.mkfifo(path)
    assert fu._memo() == {}
    assert fu.to_si("1 mi", "length", "x") == 1609.344


def test_a_kinds_own_si_unit_is_exact_and_asks_pint_nothing(monkeypatch):
    """Every kind's SI unit reads as factor 1 without pint (a copied Fault re-reads its SI values: Fault.with_
    built pint's registry, 0.2 s, in every rate-and-state run of the older scene form), and agrees with what
    pint says of it; a Fault copied with one change keeps every other value bit for bit."""
    import faultslip.units as units_module
    from faultslip.fault.scaling import Fault

    kinds = [kind for kind, spec in units_module.KINDS.items() if spec[1] and kind != "angle"]
    for kind in kinds:
        assert units_module._pint_unit_factor(units_module.KINDS[kind][1].replace("^", "**"), kind) == (1.0, "")
    fault = Fault(lithology="granodiorite", zone_width="13 mi", shear_stress="250 bar", slip_rate="2 in/yr",
                  rupture_length="270 mi", seismogenic_depth="12 km", density="2700 kg/m^3")

    def no_registry():
        raise AssertionError("pint's registry was built")

    monkeypatch.setattr(units_module, "registry", no_registry)
    units_module._unit_factor.cache_clear()
    for kind in kinds:
        si = units_module.KINDS[kind][1]
        assert to_si(f"2.5 {si}", kind, kind) == 2.5
    copied = fault.with_(radiation_damping=True)
    assert copied.radiation_damping and not fault.radiation_damping
    for name in ("shear_modulus", "zone_width", "shear_stress", "slip_rate", "rupture_length", "seismogenic_depth",
                 "density", "mu_so", "mu_m", "b", "d"):
        assert getattr(copied, name) == getattr(fault, name), name
