"""A fit bundle (issue 46, item 5): written beside a fit, readable without faultslip, replayed bit for bit, moved
numbers named, and every malformed bundle refused in one sentence."""

import io
import hashlib
import json
import zipfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import assert_clean_error
from faultslip.errors import InputError
from faultslip.io.bundle import FORMAT, manifest_checksum, read_bundle

CONFIGS = Path(__file__).resolve().parents[3] / "configs"


def _members(path) -> dict:
    with zipfile.ZipFile(path) as archive:
        return {name: archive.read(name) for name in archive.namelist()}


def _rewrite(path, members: dict) -> None:
    with zipfile.ZipFile(path, "w") as archive:
        for name, data in members.items():
            archive.writestr(name, data)


def _signed(members: dict) -> dict:
    """The members with the manifest's checksums made to match them: a bundle written elsewhere, not tampered."""
    manifest = json.loads(members["manifest.json"])
    manifest["members"] = {name: hashlib.sha256(members[name]).hexdigest() for name in manifest["members"]
                           if name in members}
    manifest["checksum"] = manifest_checksum(manifest)
    return {**members, "manifest.json": json.dumps(manifest).encode()}


def _with_manifest(tmp_path, cli, change) -> Path:
    """A good bundle whose manifest ``change(manifest)`` edits in place, written as bad.zip."""
    members = _good(tmp_path, cli)
    manifest = json.loads(members["manifest.json"])
    change(manifest)
    manifest["checksum"] = manifest_checksum(manifest)  # re-signed: the check after the checksum is what is tested
    bad = tmp_path / "bad.zip"
    _rewrite(bad, {**members, "manifest.json": json.dumps(manifest).encode()})
    return bad


def test_a_rate_law_bundle_replays_bit_for_bit_and_opens_without_faultslip(cli, tmp_path):
    import xarray as xr

    bundle = tmp_path / "fit.zip"
    out = cli("fit", CONFIGS / "example_friction_data.csv", "--bootstrap", "40", "--seed", "3", "--bundle", bundle,
              "--json")
    assert out.code == 0, out.err
    members = _members(bundle)
    manifest = json.loads(members["manifest.json"])
    assert manifest["format"] == FORMAT and manifest["options"]["seed"] == 3 and manifest["options"]["bootstrap"] == 40
    assert manifest["versions"]["numpy"] == np.__version__
    assert members["record/example_friction_data.csv"] == (CONFIGS / "example_friction_data.csv").read_bytes()
    report = json.loads(members["report.json"])
    assert report["mu_so"] == out.json["mu_so"]
    # the draws are plain netCDF: xarray's scipy backend (no faultslip) reads them
    with xr.open_dataset(io.BytesIO(members["draws.nc"]), engine="scipy") as draws:
        assert draws["bootstrap"].shape == (40, 4)
        assert list(draws["bootstrap_parameter"].values) == ["mu_so", "mu_m", "b", "d"]
    replay = cli("fit", "--replay", bundle, "--json")
    assert replay.code == 0, replay.out + replay.err
    assert replay.json["identical"] and replay.json["numbers_compared"] >= 15 and not replay.json["numbers_moved"]
    assert replay.json["draws_compared"] == {"bootstrap": [40, 4]}


def test_a_rate_state_posterior_bundle_replays_bit_for_bit(cli, tmp_path):
    bundle = tmp_path / "rs.zip"
    out = cli("fit", "--law", "rate-state", CONFIGS / "example_velocity_steps.csv", "--stiffness", "1e-2 1/um",
              "--posterior", "--samples", "400", "--bootstrap", "0", "--seed", "2", "--bundle", bundle)
    assert out.code == 0, out.err
    replay = cli("fit", "--replay", bundle, "--json")
    assert replay.code == 0, replay.out + replay.err
    assert replay.json["identical"] and "posterior" in replay.json["draws_compared"]


def test_a_replay_names_what_moved_and_the_versions_that_differ(cli, tmp_path):
    bundle = tmp_path / "fit.zip"
    assert cli("fit", CONFIGS / "example_friction_data.csv", "--bootstrap", "20", "--bundle", bundle).code == 0
    members = _members(bundle)
    report = json.loads(members["report.json"])
    report["mu_so"] *= 1 + 1e-6
    manifest = json.loads(members["manifest.json"])
    manifest["versions"]["numpy"] = "0.0.1"
    members["report.json"], members["manifest.json"] = json.dumps(report).encode(), json.dumps(manifest).encode()
    _rewrite(bundle, _signed(members))
    replay = cli("fit", "--replay", bundle, "--json")
    assert replay.code == 1
    moved = {row["key"]: row for row in replay.json["numbers_moved"]}
    assert list(moved) == ["mu_so"] and moved["mu_so"]["relative_change"] == pytest.approx(1e-6, rel=1e-3)
    assert replay.json["versions_that_differ"]["numpy"] == ["0.0.1", np.__version__]


def _good(tmp_path, cli) -> dict:
    bundle = tmp_path / "good.zip"
    assert cli("fit", CONFIGS / "example_friction_data.csv", "--bootstrap", "10", "--bundle", bundle).code == 0
    return _members(bundle)


@pytest.mark.parametrize("spoil, message", [
    (lambda m: {"notes.txt": b"hello"}, "not a faultslip fit bundle"),
    (lambda m: {**m, "manifest.json": b"{not json"}, "JSON"),
    (lambda m: {**m, "manifest.json": json.dumps({**json.loads(m["manifest.json"]), "format": "x/9"}).encode()},
     "format"),
    (lambda m: {**m, "record/example_friction_data.csv": m["record/example_friction_data.csv"] + b"1,2\n"}, "SHA-256"),
    (lambda m: {k: v for k, v in m.items() if not k.startswith("record/")}, "does not hold its record"),
    (lambda m: _signed({**m, "manifest.json": json.dumps({**json.loads(m["manifest.json"]),
                                                          "record": {"name": "../x.csv", "sha256": "0"}}).encode()}),
     "not a plain file name"),
    (lambda m: _signed({**m, "manifest.json": json.dumps({**json.loads(m["manifest.json"]),
                                                          "options": {**json.loads(m["manifest.json"])["options"],
                                                                      "rm_rf": True}}).encode()}), "rm_rf"),
    (lambda m: _signed({**m, "draws.nc": b"CDF\x02garbage"}), "netCDF"),
    (lambda m: {**m, "draws.nc": b"CDF\x02garbage"}, "draws.nc does not match its SHA-256"),
])
def test_malformed_bundles_are_one_sentence(cli, tmp_path, spoil, message):
    members = spoil(_good(tmp_path, cli))
    bad = tmp_path / "bad.zip"
    _rewrite(bad, members)
    assert_clean_error(cli("fit", "--replay", bad), message)


def test_replay_refusals(cli, tmp_path):
    (tmp_path / "not.zip").write_bytes(b"PK\x03\x04 but not a zip")
    assert_clean_error(cli("fit", "--replay", tmp_path / "not.zip"), "zip")
    assert_clean_error(cli("fit", "--replay", tmp_path / "missing.zip"), "missing.zip")
    assert_clean_error(cli("fit", CONFIGS / "example_friction_data.csv", "--replay", tmp_path / "not.zip"),
                       "takes no a data file")
    assert_clean_error(cli("fit"), "needs a data file")
    assert_clean_error(cli("fit", CONFIGS / "example_friction_data.csv", "--bundle", tmp_path / "fit.txt"), ".zip")


@settings(max_examples=60, deadline=None)
@given(data=st.binary(max_size=2000), zipped=st.booleans())
def test_the_bundle_reader_refuses_anything_else_in_one_sentence(tmp_path_factory, data, zipped):
    path = tmp_path_factory.mktemp("fuzz") / "fuzz.zip"
    if zipped:
        buffer = io.BytesIO()
        with zipfile.ZipFile(buffer, "w") as archive:
            archive.writestr("manifest.json", data)
            archive.writestr("report.json", data)
        data = buffer.getvalue()
    path.write_bytes(data)
    with pytest.raises(InputError) as raised:
        read_bundle(path)
    assert "\n" not in str(raised.value)



# Tampered bundles (issue 69): each refused in one sentence, or replayed as not identical; never "bit for bit".

def test_an_emptied_report_is_refused_by_its_checksum(cli, tmp_path):
    members = _good(tmp_path, cli)
    bad = tmp_path / "bad.zip"
    _rewrite(bad, {**members, "report.json": b"{}"})
    assert_clean_error(cli("fit", "--replay", bad), "report.json does not match its SHA-256")


def test_numbers_stored_as_strings_are_refused_by_the_checksum(cli, tmp_path):
    members = _good(tmp_path, cli)
    report = json.loads(members["report.json"])
    tripled = {key: (str(3 * value) if isinstance(value, float) else value) for key, value in report.items()}
    bad = tmp_path / "bad.zip"
    _rewrite(bad, {**members, "report.json": json.dumps(tripled).encode()})
    assert_clean_error(cli("fit", "--replay", bad), "report.json does not match its SHA-256")


def test_a_report_with_nothing_to_compare_is_not_called_identical(cli, tmp_path):
    """Even signed (as if made elsewhere), an empty report shows nothing: the replay says so and exits 1."""
    members = _good(tmp_path, cli)
    bad = tmp_path / "bad.zip"
    _rewrite(bad, _signed({**members, "report.json": b"{}"}))
    replay = cli("fit", "--replay", bad, "--json")
    assert replay.code == 1 and replay.json["identical"] is False
    assert replay.json["numbers_compared"] == 0 and replay.json["numbers_only_in_replay"]


def test_a_second_entry_that_shadows_the_first_is_refused(cli, tmp_path):
    members = _good(tmp_path, cli)
    bad = tmp_path / "bad.zip"
    with zipfile.ZipFile(bad, "w") as archive:
        for name, data in members.items():
            archive.writestr(name, data)
        with pytest.warns(UserWarning, match="Duplicate name"):
            archive.writestr("report.json", b"{}")
    assert_clean_error(cli("fit", "--replay", bad), "twice")


def test_a_bundle_of_the_older_format_is_refused_with_the_reason(cli, tmp_path):
    bad = _with_manifest(tmp_path, cli, lambda manifest: (manifest.update(format="faultslip-fit-bundle/1"),
                                                          manifest.pop("members")))
    assert_clean_error(cli("fit", "--replay", bad), "checksum for every member")


def test_an_inflating_manifest_is_refused_before_it_is_inflated(cli, tmp_path):
    """A 600 MB manifest of spaces deflates to about 600 kB: refused from its declared size, never inflated."""
    members = _good(tmp_path, cli)
    bomb = tmp_path / "bomb.zip"
    with zipfile.ZipFile(bomb, "w", compression=zipfile.ZIP_DEFLATED) as archive:
        for name, data in members.items():
            if name == "manifest.json":
                data = data + b" " * (600 * 2**20)
            archive.writestr(name, data)
    assert bomb.stat().st_size < 2**20
    assert_clean_error(cli("fit", "--replay", bomb), "manifest.json")


def test_the_bundle_option_kinds_are_the_fit_parsers_own():
    """FIT_OPTION_KINDS and FIT_OPTION_CHOICES say what the fit's parser declares: they cannot drift apart."""
    from faultslip.cli.lab import FIT_OPTION_CHOICES, FIT_OPTION_KINDS, FIT_OPTIONS, FIT_OPTIONS_NOT_NONE
    from faultslip.cli.main import build_parser

    parser = build_parser()
    commands = next(action for action in parser._actions if action.__class__.__name__ == "_SubParsersAction")
    declared = {action.dest: action for action in commands.choices["fit"]._actions if action.dest in FIT_OPTIONS}
    assert set(declared) == set(FIT_OPTIONS)
    for name, action in declared.items():
        kind = ("switch" if type(action).__name__ == "_StoreTrueAction" else
                "texts" if type(action).__name__ == "_AppendAction" else
                "count" if action.type is int else "text")
        assert FIT_OPTION_KINDS[name] == kind, name
        assert FIT_OPTION_CHOICES.get(name) == (tuple(action.choices) if action.choices else None), name
        assert (name in FIT_OPTIONS_NOT_NONE) == (action.default is not None), name


@pytest.mark.parametrize("options, message", [
    ({"bootstrap": "many"}, "'bootstrap' holds 'many'"),
    ({"posterior": "yes"}, "'posterior' holds 'yes'"),
    ({"joint": "other.csv"}, "'joint' holds 'other.csv'"),
    ({"detrend": "cubic"}, "'detrend' is 'cubic'"),
    ({"seed": 1.5}, "'seed' holds 1.5"),
    ({"seed": None}, "'seed' holds None"),
])
def test_a_bundle_option_of_the_wrong_kind_is_one_sentence(cli, tmp_path, options, message):
    bad = _with_manifest(tmp_path, cli, lambda manifest: manifest["options"].update(options))
    assert_clean_error(cli("fit", "--replay", bad), message)


def test_a_manifest_whose_versions_is_not_a_table_is_one_sentence(cli, tmp_path):
    bad = _with_manifest(tmp_path, cli, lambda manifest: manifest.update(versions=["numpy", "2.0"]))
    assert_clean_error(cli("fit", "--replay", bad), "versions is not a table")


def test_a_manifest_edited_after_writing_is_refused(cli, tmp_path):
    """Its options changed (even to what they were by default) without its checksum: refused, not replayed."""
    members = _good(tmp_path, cli)
    manifest = json.loads(members["manifest.json"])
    manifest["options"]["joint"] = None
    manifest["options"]["bootstrap"] = 11
    bad = tmp_path / "bad.zip"
    _rewrite(bad, {**members, "manifest.json": json.dumps(manifest).encode()})
    assert_clean_error(cli("fit", "--replay", bad), "manifest does not match its SHA-256")


_CHILD = """
import resource, sys
from faultslip.cli.main import main
before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
code = main(["fit", "--replay", sys.argv[1]])
print(code, (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before) / 1024)
"""


@pytest.mark.parametrize("member", ["manifest.json", "record/example_friction_data.csv"])
def test_a_bundle_bomb_stays_under_100_mb_over_the_interpreters_own(cli, tmp_path, member):
    """Issue 69: a 614 kB bundle inflated a 600 MB manifest (1.4 GB RSS), and a 600 MB record was inflated to a
    temporary folder before its limit refused it. Each is refused from the member's declared size and ratio; the
    replay, in a fresh interpreter with the command line loaded, grows its peak memory by under 100 MB."""
    import subprocess
    import sys

    members = _good(tmp_path, cli)
    bomb = tmp_path / "bomb.zip"
    with zipfile.ZipFile(bomb, "w", compression=zipfile.ZIP_DEFLATED) as archive:
        for name, data in members.items():
            if name == member:
                with archive.open(name, "w", force_zip64=True) as stream:
                    stream.write(data)
                    for _ in range(600):
                        stream.write(b" " * 2**20)
            else:
                archive.writestr(name, data)
    assert bomb.stat().st_size < 2**20
    done = subprocess.run([sys.executable, "-c", _CHILD, str(bomb)], capture_output=True, text=True, timeout=300)
    code, grown = done.stdout.split()[-2:]
    assert int(code) == 2 and "Traceback" not in done.stderr and len(done.stderr.strip().splitlines()) == 1
    assert member.split("/")[-1] in done.stderr
    assert float(grown) < 100, grown
    print(f"{member}: peak grew {float(grown):.1f} MB")
