"""One guarded door in and out (issue 26): the reader gate, the writer guard, checksummed stores.

Every case here was a traceback, a silent wrong answer or a lost file in the audit; each now exits
0 with a right answer or 2 with one sentence, and leaves no file behind.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from hypothesis import given, strategies as st

from conftest import assert_clean_error, mounted_tmpfs
from faultslip.errors import InputError
from faultslip.io import gate
from faultslip.io.outputs import output_lock

ROOT = Path(__file__).resolve().parents[3]
CONFIGS = ROOT / "configs"


# --- the reader gate -----------------------------------------------------------------------------

@pytest.mark.parametrize("argv", [
    ["record", "/dev/zero", "--stiffness", "1 N/m", "--normal-load", "1 N"],
    ["fit", "/dev/zero"],
    ["run", "/dev/zero"],
    ["catalog", "/dev/zero", "--fault", "parkfield.toml"],
])
def test_a_device_is_refused_before_a_byte_is_read(cli, argv):
    assert_clean_error(cli(*argv), "/dev/zero")


def test_a_fifo_is_refused_without_blocking(tmp_path, cli):
    fifo = tmp_path / "scene.toml"
    os.mkfifo(fifo)
    assert_clean_error(cli("run", fifo), "pipe")


def test_a_study_whose_base_is_a_device_is_refused(tmp_path, cli):
    study = tmp_path / "study.toml"
    study.write_text((CONFIGS / "study_spring_slider.toml").read_text(encoding="utf-8")
                     .replace('base = "san_andreas_1906.toml"', 'base = "/dev/zero"'), encoding="utf-8")
    assert 'base = "/dev/zero"' in study.read_text(encoding="utf-8")
    assert_clean_error(cli("sweep", study, "-o", tmp_path / "s.nc"), "device")
    assert not list(tmp_path.glob("s.nc*"))


def test_a_file_over_its_kinds_limit_names_the_limit(tmp_path):
    path = tmp_path / "big.csv"
    path.write_bytes(b"x" * 2048)
    with pytest.raises(InputError, match="the limit for such a file is 1 kiB"):
        gate.read_bytes(path, "table", limit=1024)


@given(depth=st.integers(min_value=gate.MAX_TOML_DEPTH + 1, max_value=3000),
       opener=st.sampled_from(["[", "{ a = "]))
def test_toml_nested_beyond_the_limit_is_one_sentence(depth, opener):
    closer = "]" if opener == "[" else " }"
    text = "x = " + opener * depth + closer * depth + "\n"
    with pytest.raises(InputError, match="nests arrays or tables more than"):
        gate.parse_toml(text, "deep.toml")


@given(depth=st.integers(min_value=1, max_value=gate.MAX_TOML_DEPTH))
def test_toml_within_the_limit_parses(depth):
    assert gate.parse_toml("x = " + "[" * depth + "]" * depth + "\n", "ok.toml")["x"] is not None


def test_brackets_inside_strings_and_comments_do_not_count():
    text = 'a = "[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[["  # {{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{{\nb = \'[[[[\'\n'
    assert gate.toml_depth(text) == 0
    assert gate.parse_toml(text, "s.toml")["b"] == "[[[["


def test_deep_toml_in_every_reader_is_one_sentence(tmp_path, cli):
    deep = "x = " + "[" * 600 + "]" * 600 + "\n"
    for name, argv in [("scene.toml", ["run"]), ("study.toml", ["sweep"]), ("map.toml", ["map"])]:
        path = tmp_path / name
        path.write_text(deep, encoding="utf-8")
        extra = ["-o", tmp_path / "o.nc"] if argv[0] in ("sweep", "map") else []
        assert_clean_error(cli(*argv, path, *extra), "nests")


def test_a_damaged_miniseed_is_one_line_without_obspys_chatter(tmp_path):
    """obspy prints 'Exception ignored' reports for a flipped header byte: the user sees one line."""
    good = tmp_path / "g.mseed"
    assert _run("simulate", "lab_glass_dry.toml", "--cycles", "3", "--stream", good).returncode == 0
    damaged = tmp_path / "d.mseed"
    raw = bytearray(good.read_bytes())
    raw[46] ^= 0xFF  # the blockette offset: obspy's C reader complains record after record
    damaged.write_bytes(bytes(raw))
    result = _run("record", damaged, "--stiffness", "1 N/m", "--normal-load", "1 N")
    assert result.returncode == 2
    assert len(result.stderr.strip().splitlines()) == 1, result.stderr


class _Chattering:
    """A half-built decoder object: in a reference cycle, its finaliser raises (as obspy's do)."""

    finalised = 0

    def __init__(self):
        self.cycle = self

    def __del__(self):
        type(self).finalised += 1
        raise RuntimeError("chatter from a finaliser")


def test_quiet_collects_what_the_decoder_made_in_every_generation_and_swallows_its_reports(monkeypatch):
    """gate.quiet scans only what was made inside it (the rest of the heap is frozen: a full collection of a
    long session's heap took 0.5 s a file), but all of that: a decoder's garbage already promoted to the oldest
    generation is finalised inside too, and its report is swallowed."""
    import gc

    reports = []
    monkeypatch.setattr(sys, "unraisablehook", reports.append)
    before = _Chattering.finalised
    with gate.quiet():
        assert gc.get_freeze_count() > 0  # the heap from before is set aside
        kept = _Chattering()
        gc.collect()
        gc.collect()  # survived twice: in the oldest generation now
        del kept  # garbage there, for the exit's collection
    assert _Chattering.finalised == before + 1 and reports == []
    assert gc.get_freeze_count() == 0  # and given back


def _run(*argv, cwd=None):
    return subprocess.run([sys.executable, "-m", "faultslip.cli", *map(str, argv)], capture_output=True, text=True,
                          cwd=cwd, timeout=300)


# --- the writer guard ----------------------------------------------------------------------------

HOLDER = textwrap.dedent("""
    import sys, time
    from faultslip.io.outputs import output_lock
    with output_lock(sys.argv[1], sys.argv[2]):
        print("held", flush=True)
        time.sleep(60)
""")

#: One command of each writer kind, each writing OUT (a netCDF, Zarr, PNG, GIF, NRML, QuakeML, miniSEED, SAC).
WRITERS = {
    "sweep netCDF": ["sweep", CONFIGS / "study_spring_slider.toml", "-o", "OUT.nc"],
    "sweep Zarr": ["sweep", CONFIGS / "study_spring_slider.toml", "-o", "OUT.zarr"],
    "map netCDF": ["map", CONFIGS / "san_andreas_map.toml", "-o", "OUT.nc"],
    "map figure": ["map", CONFIGS / "san_andreas_map.toml", "-o", "other.nc", "--plot", "OUT.png"],
    "map NRML": ["map", CONFIGS / "san_andreas_map.toml", "-o", "other.nc", "--nrml", "OUT.xml"],
    "fit figure": ["fit", CONFIGS / "example_friction_data.csv", "--plot", "OUT.png"],
    "simulate netCDF": ["simulate", "lab_glass_dry.toml", "--cycles", "3", "-o", "OUT.nc"],
    "simulate miniSEED": ["simulate", "lab_glass_dry.toml", "--cycles", "3", "--stream", "OUT.mseed"],
    "simulate QuakeML": ["simulate", "san_andreas_1906.toml", "--cycles", "3", "--events", "OUT.xml"],
    "animate GIF": ["animate", "lab_glass_dry.toml", "-o", "OUT.gif", "--frames", "4"],
    "convert": ["convert", CONFIGS / "example_lab_glass.zarr", "-o", "OUT.nc"],
    "figure": ["plot", "rate-law", "-o", "OUT.png"],
}


@pytest.fixture
def held(tmp_path):
    """A second process holding the lock of an output, as a running sweep, map or fit would."""
    processes = []

    def hold(path, command):
        process = subprocess.Popen([sys.executable, "-c", HOLDER, str(path), command], stdout=subprocess.PIPE,
                                   text=True)
        assert process.stdout.readline().strip() == "held"
        processes.append(process)

    yield hold
    for process in processes:
        process.kill()
        process.wait()


@pytest.mark.parametrize("holder", ["faultslip sweep", "faultslip map", "faultslip fit"])
@pytest.mark.parametrize("writer", sorted(WRITERS))
def test_every_writer_kind_refuses_a_second_writer_of_any_kind(tmp_path, monkeypatch, cli, held, writer, holder):
    monkeypatch.chdir(tmp_path)
    argv = [str(a) for a in WRITERS[writer]]
    target = next(a for a in argv if a.startswith("OUT."))
    held(tmp_path / target, holder)
    result = cli(*argv)
    assert_clean_error(result, "being written by another faultslip run", holder)
    assert not (tmp_path / target).exists()
    assert not (tmp_path / "other.nc").exists()  # the command's other outputs are not left behind either


def test_a_symlink_planted_at_the_lock_is_never_followed(tmp_path, cli):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious", encoding="utf-8")
    (tmp_path / ".out.nc.lock").symlink_to(victim)
    result = cli("simulate", "lab_glass_dry.toml", "--cycles", "3", "-o", tmp_path / "out.nc")
    assert_clean_error(result, "symbolic link")
    assert victim.read_text(encoding="utf-8") == "precious"
    assert not (tmp_path / "out.nc").exists()


def test_a_hard_link_planted_at_the_lock_is_refused_and_not_truncated(tmp_path, cli):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious", encoding="utf-8")
    os.link(victim, tmp_path / ".out.nc.lock")
    assert_clean_error(cli("simulate", "lab_glass_dry.toml", "--cycles", "3", "-o", tmp_path / "out.nc"),
                       "not a plain file")
    assert victim.read_text(encoding="utf-8") == "precious"


def test_a_stale_lock_of_a_killed_run_does_not_block(tmp_path, cli):
    (tmp_path / ".out.nc.lock").write_text(json.dumps({"pid": 999999, "command": "faultslip sweep",
                                                        "started": 0}), encoding="utf-8")
    assert cli("simulate", "lab_glass_dry.toml", "--cycles", "3", "-o", tmp_path / "out.nc").code == 0
    assert (tmp_path / "out.nc").exists() and not (tmp_path / ".out.nc.lock").exists()


def test_the_existence_check_is_taken_with_the_lock(tmp_path):
    """Two runs cannot both find an output absent: under the lock, an output that appeared is refused."""
    target = tmp_path / "out.nc"
    target.write_text("written by the first run", encoding="utf-8")
    with pytest.raises(InputError, match="already exists"), output_lock(target, "second", overwrite=False):
        pass


def test_a_command_that_fails_late_leaves_none_of_its_outputs(tmp_path, cli, monkeypatch):
    """map writes its netCDF, then fails on the figure: neither remains (one transaction per command)."""
    # the command's module is imported before either name is patched: imported first under the patch, it would
    # bind the broken figure as its own, and the patch's undo would restore that for every later test in the process
    import faultslip.cli.studies as studies_cli
    import faultslip.studies.maps as maps

    def broken(dataset):
        raise InputError("the figure could not be drawn")

    monkeypatch.setattr(maps, "map_figure", broken)
    monkeypatch.setattr(studies_cli, "map_figure", broken)
    result = cli("map", CONFIGS / "san_andreas_map.toml", "-o", tmp_path / "m.nc", "--plot", tmp_path / "m.png")
    assert_clean_error(result, "figure")
    assert sorted(p.name for p in tmp_path.iterdir()) == []


@pytest.fixture
def full_disk(tmp_path):
    """A tmpfs of 300 kB (root only); skipped where mounting is not allowed."""
    with mounted_tmpfs(tmp_path / "full", "300k") as mount:
        yield mount


@pytest.mark.parametrize("argv", [
    ["map", CONFIGS / "california_faults_map.toml", "-o", "FULL/m.nc", "--plot", "FULL/m.png"],
    ["sweep", CONFIGS / "study_spring_slider.toml", "-o", "FULL/s.nc", "--allow-large"],
    ["sweep", CONFIGS / "study_spring_slider.toml", "-o", "FULL/s.zarr", "--allow-large"],
    ["simulate", "lab_glass_dry.toml", "--stream", "FULL/g.mseed"],
])
def test_a_full_disk_is_one_sentence_and_leaves_nothing(full_disk, argv):
    (full_disk / "pad").write_bytes(b"\0" * 150_000)
    result = _run(*[str(a).replace("FULL", str(full_disk)) for a in argv])
    assert result.returncode == 2, result.stderr
    assert len(result.stderr.strip().splitlines()) == 1, result.stderr
    assert "full" in result.stderr or "disk" in result.stderr
    assert sorted(p.name for p in full_disk.iterdir()) == ["pad"]


# --- checksummed stores --------------------------------------------------------------------------

@pytest.fixture
def store(tmp_path):
    copy = tmp_path / "s.zarr"
    shutil.copytree(CONFIGS / "example_lab_glass.zarr", copy)
    return copy


def _flip(path: Path, position: float = 0.5) -> None:
    raw = bytearray(path.read_bytes())
    raw[int(len(raw) * position)] ^= 0x10
    path.write_bytes(bytes(raw))


@pytest.mark.parametrize("damage, needle", [
    (lambda s: (s / "slip_per_event" / "0.0").unlink(), "missing chunk 0.0 of 'slip_per_event'"),
    (lambda s: _flip(s / "slip_per_event" / "0.0"), "slip_per_event"),
    (lambda s: _flip(s / "loading_rate" / "0"), "zarr store"),
    (lambda s: _edit_attrs(s / ".zattrs", None), "null"),
    (lambda s: _edit_attrs(s / "slip_per_event" / ".zattrs", {"a": 1}), "a table"),
])
def test_a_damaged_store_is_refused_by_name_and_never_filled(store, tmp_path, cli, damage, needle):
    damage(store)
    result = cli("convert", store, "-o", tmp_path / "c.nc")
    assert_clean_error(result, needle)
    assert not list(tmp_path.glob("c.nc*"))


def _edit_attrs(path: Path, value) -> None:
    """An attribute netCDF cannot hold, in a store sealed again after it (as a writer other than faultslip's
    sweep might leave one): what convert refuses is the value, not the checksum."""
    from faultslip.io.zarr_store import seal_store

    attrs = json.loads(path.read_text(encoding="utf-8"))
    attrs["bad"] = value
    path.write_text(json.dumps(attrs), encoding="utf-8")
    store = next(parent for parent in [path.parent, *path.parents] if (parent / ".zgroup").is_file()
                 and (parent / ".zmetadata").is_file())
    (store / ".zmetadata").unlink()
    seal_store(store)


def test_an_intact_store_converts_to_the_values_it_holds(store, tmp_path, cli):
    import xarray as xr

    from faultslip.io.netcdf import CHECKSUM_ATTRIBUTE, COVERS_ATTRIBUTE
    from faultslip.io.zarr_store import CHECKSUM, COVERS, DIGESTS

    assert cli("convert", store, "-o", tmp_path / "c.nc").code == 0
    own = (CHECKSUM_ATTRIBUTE, COVERS_ATTRIBUTE, CHECKSUM, COVERS, DIGESTS)
    with xr.open_zarr(store) as original, xr.open_dataset(tmp_path / "c.nc") as converted:
        # the blocks' digests and the metadata's checksum belong to the store, and stay with it; the file carries
        # its own checksum, of itself
        assert DIGESTS in original.attrs and DIGESTS not in converted.attrs
        assert original.attrs[CHECKSUM] != converted.attrs[CHECKSUM_ATTRIBUTE]
        assert original.attrs[COVERS] != converted.attrs[COVERS_ATTRIBUTE]
        xr.testing.assert_identical(original.load().drop_attrs(deep=False).assign_attrs(
            {k: v for k, v in original.attrs.items() if k not in own}),
            converted.load().drop_attrs(deep=False).assign_attrs(
                {k: v for k, v in converted.attrs.items() if k not in own}))


def test_a_store_without_checksums_is_refused(store, tmp_path, cli):
    meta = store / "slip_per_event" / ".zarray"
    array = json.loads(meta.read_text(encoding="utf-8"))
    array["filters"] = [f for f in array["filters"] if f["id"] != "crc32c"]
    meta.write_text(json.dumps(array), encoding="utf-8")
    assert_clean_error(cli("convert", store, "-o", tmp_path / "c.nc"), "edited or damaged")  # the metadata changed
    from faultslip.io.zarr_store import seal_store

    (store / ".zmetadata").unlink()
    seal_store(store)  # sealed as it now is: its chunks' own checksums are what is missing
    assert_clean_error(cli("convert", store, "-o", tmp_path / "c.nc"), "no checksum")


def test_a_lock_removed_between_its_two_opens_is_created_again(tmp_path, monkeypatch):
    """A holder that finishes unlinks its lock; a claimant whose O_EXCL create found it, and whose plain open
    then finds nothing, creates it afresh instead of refusing (concurrent fits lost one this way)."""
    import os

    from faultslip.io import outputs

    lock = tmp_path / ".o.nc.lock"
    lock.write_text("", encoding="utf-8")
    real_open, calls = os.open, []

    def racing_open(path, flags, *args):
        calls.append(flags)
        if not flags & os.O_CREAT and len(calls) == 2:  # the holder unlinks it just now
            os.unlink(path)
            raise FileNotFoundError(2, "No such file or directory")
        return real_open(path, flags, *args)

    monkeypatch.setattr(outputs.os, "open", racing_open)
    descriptor = outputs._open_lock(lock)
    os.close(descriptor)
    assert len(calls) == 3 and calls[2] & os.O_EXCL and lock.is_file()


# Archives are bounded before anything is inflated or allocated (issue 69): zip members by their declared sizes
# and ratios, array members by their headers. Each bomb runs in a child process whose peak memory is measured.

_PEAK = textwrap.dedent("""
    import resource, sys
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    from faultslip.errors import InputError
    {body}
    after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    print(message)
    print((after - before) / 1024)
""")


def _peak(body: str) -> tuple[str, float]:
    """Run ``body`` (which sets ``message``) in a fresh interpreter: (message, peak memory growth in MiB)."""
    done = subprocess.run([sys.executable, "-c", _PEAK.format(body=textwrap.dedent(body).strip())],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    message, grown = done.stdout.strip().splitlines()[-2:]
    return message, float(grown)


def _refusal(module: str, function: str, arguments: str) -> tuple[str, float]:
    """``module.function(arguments)`` in a fresh interpreter: (its refusal's sentence, or "accepted"; peak memory
    growth in MiB)."""
    return _peak(f"""
        from {module} import {function}
        try:
            {function}({arguments})
            message = "accepted"
        except InputError as exc:
            message = str(exc)
    """)


def _npy_header(shape, dtype="<f8") -> bytes:
    """A .npy file's magic and header (numpy's own writer) for an array of ``shape``."""
    import io as _io

    import numpy as np

    buffer = _io.BytesIO()
    np.lib.format.write_array_header_1_0(buffer, {"descr": dtype, "fortran_order": False, "shape": shape})
    return buffer.getvalue()


def _zeros_npz(path, name: str, declared_shape, written_bytes: int) -> None:
    """An .npz whose member ``name`` has a header of ``declared_shape`` (float64) and ``written_bytes`` of zeros,
    written in pieces (the test never holds the array)."""
    import zipfile

    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED) as archive:
        with archive.open(name + ".npy", "w", force_zip64=True) as stream:
            stream.write(_npy_header(declared_shape))
            left = written_bytes
            while left:
                stream.write(b"\0" * min(left, 2**20))
                left -= min(left, 2**20)


def test_a_checkpoint_whose_header_claims_more_than_it_holds_is_refused_before_allocating(tmp_path):
    bomb = tmp_path / "checkpoint.npz"
    _zeros_npz(bomb, "slip", (200_000_000,), 2**19)  # 1.6 GB claimed, 512 kiB held
    message, grown = _refusal("faultslip.io.records", "read_checkpoint", f"{str(bomb)!r}, {{'slip': ('f', (None,))}}")
    assert "declares" in message and "slip.npy" in message
    assert grown < 100


def test_a_checkpoint_that_inflates_a_thousandfold_is_refused_before_inflating(tmp_path):
    bomb = tmp_path / "checkpoint.npz"
    _zeros_npz(bomb, "slip", (300 * 2**20 // 8,), 300 * 2**20)  # 300 MiB of zeros deflate to about 300 kB
    assert bomb.stat().st_size < 2 * 2**20
    message, grown = _refusal("faultslip.io.records", "read_checkpoint", f"{str(bomb)!r}, {{'slip': ('f', (None,))}}")
    assert "to 1" in message and "zip bomb" in message
    assert grown < 100


def test_a_zip_member_past_its_declared_limit_names_the_member():
    import io as _io
    import zipfile

    buffer = _io.BytesIO()
    with zipfile.ZipFile(buffer, "w") as archive:
        archive.writestr("a.json", b"x" * 2048)
    with pytest.raises(InputError, match="a.json.*inflates to 2 kiB, past the limit of 1 kiB"):
        gate.open_zip(buffer.getvalue(), "x.zip", "the test archive", total_limit=10**6, member_limits={"a.json": 1024})


def test_a_workbook_with_one_cell_at_the_last_column_and_row_is_refused_from_its_dimension(tmp_path):
    """A 10 kB workbook with one stray cell at XFD1048576 declares 1.7e10 cells: refused before a row is read."""
    openpyxl = pytest.importorskip("openpyxl")
    book = openpyxl.Workbook()
    sheet = book.active
    sheet["A1"], sheet["B1"], sheet["A2"], sheet["B2"] = "time (s)", "load (N)", 1.0, 2.0
    sheet["XFD1048576"] = 3.0
    path = tmp_path / "far.xlsx"
    book.save(path)
    message, grown = _refusal("faultslip.io.resources", "read_numeric_xlsx", f"{str(path)!r}, 'the record'")
    assert "A1:XFD1048576" in message and "clear the cells outside the table" in message
    assert grown < 100


def test_a_workbook_whose_sheet_inflates_a_thousandfold_is_refused_before_inflating(tmp_path):
    import zipfile

    openpyxl = pytest.importorskip("openpyxl")
    book = openpyxl.Workbook()
    book.active["A1"], book.active["A2"] = "time (s)", 1.0
    good = tmp_path / "good.xlsx"
    book.save(good)
    bomb = tmp_path / "bomb.xlsx"
    with zipfile.ZipFile(good) as source, zipfile.ZipFile(bomb, "w", compression=zipfile.ZIP_DEFLATED) as target:
        for info in source.infolist():
            data = source.read(info)
            if info.filename == "xl/worksheets/sheet1.xml":
                with target.open(info.filename, "w", force_zip64=True) as stream:
                    stream.write(data.replace(b"<sheetData>", b"<sheetData>" + b" " * 2**20, 1))
                    for _ in range(299):
                        stream.write(b" " * 2**20)
                continue
            target.writestr(info, data)
    assert bomb.stat().st_size < 2 * 2**20
    message, grown = _refusal("faultslip.io.resources", "read_numeric_xlsx", f"{str(bomb)!r}, 'the record'")
    assert "zip bomb" in message and "sheet1.xml" in message
    assert grown < 100


def test_repeated_names_are_found_once_each_in_linear_time():
    """A 20,004-column header took over a minute when each name was counted across the list."""
    names = [f"c{k}" for k in range(20_000)] + ["c7", "c7", "c19999", "c0"]
    assert gate.repeated_names(names) == ["c0", "c19999", "c7"]
    assert gate.repeated_names([]) == [] and gate.repeated_names(["a", "b"]) == []


def test_a_header_of_twenty_thousand_columns_is_read(tmp_path):
    from faultslip.io.resources import read_numeric_csv

    path = tmp_path / "wide.csv"
    path.write_text(",".join(f"c{k} (m)" for k in range(20_004)) + "\n" + ",".join("1" for _ in range(20_004)) + "\n")
    table = read_numeric_csv(path, "the wide table")
    assert len(table) == 20_004 and table["c20003"][1] == "m"
