"""Every reader and the unit parser, fuzzed: any input gives a value or one InputError, nothing else.

The mutations are those of ``benchmarks/fuzz.py`` (which runs 10,000+ cases through the CLI);
here hypothesis drives them, bounded in time, so the suite keeps the property.
"""

import random
import statistics
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import load_benchmark
from faultslip.errors import InputError
from faultslip.units import KINDS, to_si

ROOT = Path(__file__).resolve().parents[3]
fuzz = load_benchmark("fuzz", "faultslip_fuzz")

SCENES = sorted(p for p in (ROOT / "configs").glob("*.toml") if "[scene]" in p.read_text(encoding="utf-8"))
FUZZ = settings(deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])


def _clean(function, *args):
    try:
        function(*args)
    except InputError as exc:
        message = str(exc)
        assert message and "\n" not in message.strip() and "Traceback" not in message


QUANTITY_PIECES = st.sampled_from(["1", "0", "-", "\u2212", "1e400", ".", ",", "5", " ", "m", "km", "mi", "/", "*",
                                   "**", "^", "(", ")", "s", "yr", "in", "bar", "lbf", "g_0", "rad", "Hz", "1/", "e",
                                   "nan", "inf", "%", "\u00b5", "\u00b7", "__", "import", "[", "'", "\\", "\x00",
                                   "degC", "1j", "2", "3.5", "m^2", "s^-1"])


@FUZZ
@given(text=st.one_of(st.text(max_size=30), st.lists(QUANTITY_PIECES, max_size=8).map("".join)),
       kind=st.sampled_from(sorted(KINDS)))
def test_unit_parser_returns_a_finite_number_or_one_sentence(text, kind):
    try:
        value = to_si(text, kind, "x")
    except InputError as exc:
        assert "\n" not in str(exc)
    else:
        assert value == value and abs(value) != float("inf")


def _mutated(seed_text, mutate, seed):
    return mutate(seed_text, random.Random(seed))


def _write(path, content):
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content, encoding="utf-8", errors="surrogatepass")
    return path


@FUZZ
@given(scene=st.sampled_from(SCENES), seed=st.integers(0, 2**32))
def test_scene_reader(tmp_path_factory, scene, seed):
    from faultslip.fault.scene import read_slider_scene

    path = _write(tmp_path_factory.mktemp("scene") / "scene.toml",
                  _mutated(scene.read_text(encoding="utf-8"), fuzz.mutate_toml, seed))

    def read_and_build():
        loaded = read_slider_scene(path)
        loaded.slider()

    _clean(read_and_build)


@FUZZ
@given(study=st.sampled_from(["study_spring_slider.toml", "study_lab_glass.toml", "study_rate_state.toml"]),
       seed=st.integers(0, 2**32))
def test_study_reader(tmp_path_factory, study, seed):
    from faultslip.studies.grid import load_study

    text = (ROOT / "configs" / study).read_text(encoding="utf-8").replace('base = "', f'base = "{ROOT}/configs/')
    path = _write(tmp_path_factory.mktemp("study") / "study.toml", _mutated(text, fuzz.mutate_toml, seed))
    _clean(load_study, path)


@FUZZ
@given(seed=st.integers(0, 2**32))
def test_vibration_scene_reader_and_analysis(tmp_path_factory, seed):
    """A mutated quasi-harmonic scene is read and analysed, or refused in one sentence."""
    from faultslip.models.vibration.scene import read_vibration_scene

    text = (ROOT / "configs" / "vibration_seed002.toml").read_text(encoding="utf-8")
    path = _write(tmp_path_factory.mktemp("vibration") / "v.toml", _mutated(text, fuzz.mutate_toml, seed))

    def read_and_analyse():
        system, _ = read_vibration_scene(path)
        system.analyse()

    _clean(read_and_analyse)


@FUZZ
@given(seed=st.integers(0, 2**32), which=st.sampled_from(["map", "segments"]))
def test_map_and_segment_readers(tmp_path_factory, seed, which):
    from faultslip.studies.maps import read_map

    folder = tmp_path_factory.mktemp("map")
    segments = (ROOT / "data" / "san_andreas_segments.csv").read_text(encoding="utf-8")
    text = ('[map]\nbase = "san_andreas_1906.toml"\n[segments]\nfile = "segments.csv"\n[grid]\n'
            'lon = { linspace = [-124.0, -115.0, 4] }\nlat = { linspace = [33.0, 40.0, 3] }\n')
    _write(folder / "segments.csv", _mutated(segments, fuzz.mutate_csv, seed) if which == "segments" else segments)
    path = _write(folder / "map.toml", _mutated(text, fuzz.mutate_toml, seed) if which == "map" else text)
    _clean(read_map, path)


@FUZZ
@given(seed=st.integers(0, 2**32))
def test_friction_data_reader(tmp_path_factory, seed):
    from faultslip.friction.fitting import read_friction_data

    text = (ROOT / "configs" / "example_friction_data.csv").read_text(encoding="utf-8")
    _clean(read_friction_data, _write(tmp_path_factory.mktemp("fit") / "data.csv",
                                      _mutated(text, fuzz.mutate_csv, seed)))


@FUZZ
@given(seed=st.integers(0, 2**32))
def test_record_reader(tmp_path_factory, seed):
    from faultslip.lab.records import read_record

    lines = (ROOT / "configs" / "example_record.csv").read_text(encoding="utf-8").splitlines()[:300]
    _clean(read_record, _write(tmp_path_factory.mktemp("record") / "record.csv",
                               _mutated("\n".join(lines) + "\n", fuzz.mutate_csv, seed)))


@settings(deadline=None, max_examples=15, suppress_health_check=[HealthCheck.too_slow,
                                                                 HealthCheck.function_scoped_fixture])
@given(seed=st.integers(0, 2**32))
def test_netcdf_readers_survive_damaged_files(tmp_path_factory, seed):
    """A damaged netCDF can crash the netCDF library itself; the reader must still give one sentence."""
    from faultslip.friction.fitting import read_friction_data
    from faultslip.lab.records import read_record

    source = _netcdf_seed(tmp_path_factory)
    damaged = _write(tmp_path_factory.mktemp("nc") / "damaged.nc", fuzz.mutate_bytes(source, random.Random(seed)))
    _clean(read_record, damaged)
    _clean(read_friction_data, damaged)


_NETCDF = {}


def _netcdf_seed(tmp_path_factory):
    if "bytes" not in _NETCDF:
        import numpy as np
        import xarray as xr

        path = tmp_path_factory.mktemp("seed") / "record.nc"
        t = np.linspace(0, 1, 200)
        xr.Dataset({"displacement": ("time", np.sin(40 * t), {"units": "mm"})},
                   coords={"time": ("time", t, {"units": "s"})}, attrs={"title": "x" * 50}).to_netcdf(path)
        _NETCDF["bytes"] = path.read_bytes()
    return _NETCDF["bytes"]


@pytest.mark.parametrize("text, needle", [
    ("\u22125 km", None), ("1,5 km", "decimal point"), ("5 m)", "unbalanced"), ("1/0 m", "cannot read"),
    ("10**400 m", "cannot read"), ("1 m*", "ends with an operator"), ("1e400 m", "out of range"),
    ("nan m", "finite"), ("m", "start with a number"),
])
def test_the_audits_unit_strings(text, needle):
    if needle is None:
        assert to_si(text, "length", "x") == -5000.0  # a Unicode minus is a minus (it used to be dropped)
        return
    with pytest.raises(InputError, match=needle):
        to_si(text, "length", "x")


def test_a_sign_spaced_by_any_whitespace_reads_or_refuses_in_one_sentence():
    """Found by the unit-parser property: '-\\r0' matched the number pattern (\\s after the sign) but
    float() was given the carriage return and raised ValueError."""
    assert to_si("-\r5 km", "length", "x") == -5000.0
    with pytest.raises(InputError, match="bare number"):
        to_si("-\r0", "acceleration", "x")


@FUZZ
@given(seed=st.integers(0, 2**32), which=st.sampled_from(["csv", "quakeml"]))
def test_catalog_readers(tmp_path_factory, seed, which):
    """A mutated CSV or QuakeML catalog is read (every event in range) or refused in one sentence."""
    from faultslip.io.catalogs import read_catalog, write_quakeml

    folder = tmp_path_factory.mktemp("catalog")
    text = (ROOT / "configs" / "catalog_san_andreas.csv").read_text(encoding="utf-8")
    if which == "csv":
        path = _write(folder / "c.csv", _mutated(text, fuzz.mutate_csv, seed))
    else:
        source = read_catalog(ROOT / "configs" / "catalog_san_andreas.csv")
        write_quakeml(source.time, source.latitude, source.longitude, [1e4] * len(source), source.magnitude,
                      folder / "c.xml", names=source.name)
        raw = (folder / "c.xml").read_bytes()
        path = folder / "c.xml"
        mutated = _mutated(raw.decode("utf-8"), fuzz.mutate_csv, seed)  # text edits: tags, values, lines
        text_edit = mutated if isinstance(mutated, bytes) else mutated.encode("utf-8", "surrogatepass")
        path.write_bytes(fuzz.mutate_bytes(raw, random.Random(seed)) if seed % 2 else text_edit)

    def read_and_check():
        catalog = read_catalog(path)
        assert len(catalog) > 0 and (abs(catalog.latitude) <= 90).all()

    _clean(read_and_check)


@settings(FUZZ, max_examples=40)
@given(seed=st.integers(0, 2**32))
def test_miniseed_record_reader(tmp_path_factory, seed):
    """A corrupted miniSEED record is read as a record or refused in one sentence. 40 cases here (obspy takes
    about 0.5 s on a corrupted record: 100 cases were the suite's slowest test, 53 s); benchmarks/fuzz.py draws
    thousands more through 'faultslip record'."""
    import numpy as np

    from faultslip.io.waveforms import build_stream, write_stream
    from faultslip.lab.records import read_record

    folder = tmp_path_factory.mktemp("mseed")
    stream = build_stream(100.0, {"D": np.sin(np.linspace(0, 20, 600)) * 1e-4, "F": np.full(600, 0.6)}, 0.0)
    write_stream(stream, folder / "clean.mseed")
    raw = (folder / "clean.mseed").read_bytes()
    path = folder / "r.mseed"
    path.write_bytes(fuzz.mutate_bytes(raw, random.Random(seed)))
    _clean(read_record, path)


@FUZZ
@given(seed=st.integers(0, 2**32))
def test_geojson_fault_reader(tmp_path_factory, seed):
    """A mutated GAF GeoJSON fault file is read (traces in range) or refused in one sentence."""
    from faultslip.io.geojson import read_fault_geojson

    text = (ROOT / "data" / "gem_faults_example.geojson").read_text(encoding="utf-8")
    path = _write(tmp_path_factory.mktemp("geojson") / "f.geojson", _mutated(text, fuzz.mutate_csv, seed))
    _clean(read_fault_geojson, path)


@FUZZ
@given(seed=st.integers(0, 2**32))
def test_sherifs_readers(tmp_path_factory, seed):
    """Mutated SHERIFS geometry, properties and rupture files are read (traces and numbers in range) or refused in
    one sentence."""
    from faultslip.io.sherifs import read_sherifs_faults, read_sherifs_ruptures

    folder = tmp_path_factory.mktemp("sherifs")
    source = ROOT / "configs" / "sherifs_example"
    rng = random.Random(seed)
    paths = {}
    for name in ("Faults_geometry.txt", "Faults_properties.txt", "ruptures.txt"):
        text = source.joinpath(name).read_text(encoding="utf-8")
        paths[name] = _write(folder / name, fuzz.mutate_csv(text, rng) if rng.random() < 0.5 else text)
    _clean(read_sherifs_faults, paths["Faults_geometry.txt"], paths["Faults_properties.txt"])
    _clean(read_sherifs_ruptures, paths["ruptures.txt"])


@FUZZ
@given(seed=st.integers(0, 2**32))
def test_accelerometer_reader_and_analysis(tmp_path_factory, seed):
    """A mutated phyphox export is read and analysed, or refused in one sentence."""
    from faultslip.lab.classroom import analyse, read_accelerometer

    lines = (ROOT / "configs" / "example_phyphox.csv").read_text(encoding="utf-8").splitlines()[:400]
    path = _write(tmp_path_factory.mktemp("phyphox") / "p.csv", _mutated("\n".join(lines) + "\n", fuzz.mutate_csv, seed))

    def read_and_analyse():
        analyse(read_accelerometer(path))

    _clean(read_and_analyse)


@FUZZ
@given(seed=st.integers(0, 2**32))
def test_surface_reader_and_statistics(tmp_path_factory, seed):
    """A mutated surface map is read and described, or refused in one sentence."""
    from faultslip.lab.surfaces import read_surface, statistics

    lines = (ROOT / "configs" / "example_surface.csv").read_text(encoding="utf-8").splitlines()[:1025]  # 16 rows
    path = _write(tmp_path_factory.mktemp("surface") / "s.csv", _mutated("\n".join(lines) + "\n", fuzz.mutate_csv, seed))

    def read_and_describe():
        statistics(read_surface(path).levelled())

    _clean(read_and_describe)


@FUZZ
@given(seed=st.integers(0, 2**32))
def test_rough_surface_scene_reader(tmp_path_factory, seed):
    """A mutated rough-surface scene (seed 000) builds its slider or is refused in one sentence."""
    from faultslip.models.rough_surface.scene import read_rough_scene

    text = (ROOT / "configs" / "rough_surface_seed000.toml").read_text(encoding="utf-8").replace(
        "synthetic_size = 128", "synthetic_size = 32")
    _clean(read_rough_scene, _write(tmp_path_factory.mktemp("rough") / "r.toml", _mutated(text, fuzz.mutate_toml, seed)))


_INTERRUPTED = {}
_SWEEP = '[study]\nbase = "san_andreas_1906.toml"\n[sweep]\nslip_rate = ["10 mm/yr", "30 mm/yr"]\n' \
         'lithology = ["granodiorite", "pyrite"]\n'


def _interrupted_sweep(tmp_path_factory, name):
    """The seed sweep stopped after two of its four blocks (the fuzzer's partial kind), and the content of the
    same sweep without a stop."""
    if name not in _INTERRUPTED:
        from faultslip.studies.grid import parse_study
        from faultslip.studies.streaming import run_study

        folder = tmp_path_factory.mktemp("interrupted")
        study = parse_study(_SWEEP)
        fuzz.stop_sweep(study, folder / name)
        reference = folder / f"reference_{name}"
        run_study(study, reference, chunk_cells=1, workers=1, compression="none")
        _INTERRUPTED[name] = (folder, _content(reference))
    return _INTERRUPTED[name]


def _content(path):
    """A study output as xarray reads it undecoded, less the attributes two runs of one study differ in (the time
    in history) and those that seal a finished file."""
    import xarray as xr

    skip = {"history", "faultslip_checksum", "faultslip_checksum_covers", "faultslip_block_digests"}
    opener = xr.open_zarr if path.suffix == ".zarr" else xr.open_dataset
    with opener(path, decode_cf=False) as dataset:
        dataset = dataset.load()
    return dataset.drop_attrs(deep=False).assign_attrs({k: v for k, v in dataset.attrs.items() if k not in skip})


@settings(FUZZ, max_examples=20)
@given(seed=st.integers(0, 2**32), name=st.sampled_from(["sweep.nc", "sweep.zarr"]), ledger=st.booleans())
def test_a_damaged_partial_output_resumes_to_the_uninterrupted_run_or_one_sentence(tmp_path_factory, seed, name,
                                                                                   ledger):
    """An interrupted sweep's partial output (its bytes, an attribute, a coordinate, a chunk) or its progress record
    damaged before --resume: the run gives exactly what a run without a stop gives, or one sentence. A resume that
    carried an edited attribute or coordinate into the finished file would be a silent wrong answer."""
    import shutil
    import warnings

    from faultslip.studies.grid import parse_study
    from faultslip.studies.streaming import run_study

    source, expected = _interrupted_sweep(tmp_path_factory, name)
    folder = tmp_path_factory.mktemp("resume")
    for path in source.glob(f"{name}.*"):
        (shutil.copytree if path.is_dir() else shutil.copy)(path, folder / path.name)
    rng = random.Random(seed)
    if ledger:
        progress = folder / f"{name}.progress.json"
        _write(progress, fuzz.mutate_progress(progress.read_text(encoding="utf-8"), rng))
    elif name == "sweep.nc":
        fuzz.mutate_netcdf(folder / f"{name}.partial", rng)
    else:
        fuzz.damage_store(folder / f"{name}.partial", rng)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # "starting over", "recomputing": said, and not what this checks
            run_study(parse_study(_SWEEP), folder / name, chunk_cells=1, workers=1, compression="none", resume=True)
    except InputError as exc:
        assert "\n" not in str(exc).strip()
    else:
        import xarray as xr

        xr.testing.assert_identical(_content(folder / name), expected)


_LEDGER_STUDIES = {}


@settings(FUZZ, max_examples=60)
@given(seed=st.integers(0, 2**32))
def test_a_failure_ledger_changed_after_writing_is_refused_before_any_cell_runs(tmp_path_factory, seed):
    """The fuzzer's ledger kind without the sweep: a failure ledger edited (a cell dropped, an index, the count, a
    key, a reason) or its bytes mutated. --retry-failed must refuse, in one sentence naming the ledger, every one
    whose content differs from what the sweep wrote; only the ledger as written (or re-spaced) is trusted. The
    output is junk, so a ledger that got through would be refused for the output instead, and fail here."""
    from faultslip.studies.grid import parse_study
    from faultslip.studies.streaming import _write_failure_ledger, failure_ledger, retry_failed

    if "study" not in _LEDGER_STUDIES:
        folder = tmp_path_factory.mktemp("ledger")
        study = parse_study(_SWEEP)
        cells = [{"index": {"slip_rate": 0, "lithology": 1}, "values": {}, "reason": "the solver failed"},
                 {"index": {"slip_rate": 1, "lithology": 0}, "values": {}, "reason": "the solver failed"}]
        out = folder / "retry.nc"
        out.write_bytes(b"not a netCDF file")
        _write_failure_ledger(out, study, study.fingerprint(), cells)
        _LEDGER_STUDIES.update(study=study, out=out, text=failure_ledger(out).read_text(encoding="utf-8"))
    study, out, written = _LEDGER_STUDIES["study"], _LEDGER_STUDIES["out"], _LEDGER_STUDIES["text"]
    mutated = fuzz.mutate_ledger(written, random.Random(seed))
    if fuzz.ledger_content(mutated) == fuzz.ledger_content(written):
        return  # as written: a retry runs, which the slurm tests cover
    _write(failure_ledger(out), mutated)
    with pytest.raises(InputError, match="failure ledger") as refused:
        retry_failed(study, out, workers=1)
    assert "\n" not in str(refused.value).strip()


@settings(FUZZ, max_examples=60)
@given(seed=st.integers(0, 2**32))
def test_a_machine_speed_record_changed_after_writing_is_neither_used_nor_changed(tmp_path_factory, seed):
    """The fuzzer's machine kind without the CLI: a machine speed record edited, resealed past its bounds or its
    bytes mutated. Every one whose content differs from what was written is read as one sentence (the estimate's
    warning) and keeps every byte; the estimate takes this process's probe alone. One as written is used."""
    import warnings

    from faultslip.io import machine

    path = tmp_path_factory.mktemp("machine") / "machine_speed.json"
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv(machine.RECORD_ENVIRONMENT, str(path))
        for reading in (1.0e-3, 1.2e-3, 0.9e-3):
            machine.recorded_median(reading)
        written = path.read_text(encoding="utf-8")
        mutated = fuzz.mutate_machine_record(written, random.Random(seed))
        _write(path, mutated)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            median, count, _ = machine.recorded_median(2e-3)
    if fuzz.record_content(mutated) == fuzz.record_content(written):
        assert (median, count, caught) == (statistics.median([1.0e-3, 1.2e-3, 0.9e-3, 2e-3]), 4, [])
        return
    assert (median, count) == (2e-3, 1)
    assert len(caught) == 1 and "machine speed record" in str(caught[0].message)
    assert "\n" not in str(caught[0].message).strip()
    assert path.read_bytes() == (mutated.encode("utf-8") if isinstance(mutated, str) else mutated)
