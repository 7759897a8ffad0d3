"""Regional maps: the bundled San Andreas segments, rasters, geodesy, predicted against observed, bad input."""

import numpy as np
import pytest
import xarray as xr

from conftest import assert_clean_error, modelled_seconds
from faultslip.errors import InputError
from faultslip.studies.maps import read_map, nearest_segment, observed_table, parse_trace, segment_rows, read_segments, run_map, trace_length
from faultslip.io.resources import data_path

YEAR = 365.25 * 86400


@pytest.fixture(scope="module")
def bundled():
    spec = read_map("san_andreas_map.toml")
    return spec, run_map(spec)


def test_bundled_segment_table_cites_every_value():
    table = read_segments(data_path("san_andreas_segments.csv"))
    assert len(table.ids) >= 8 and "carrizo" in table.ids and "north_coast" in table.ids
    for i, segment in enumerate(table.ids):
        assert table.sources["source_slip_rate"][i], segment
        assert table.sources["source_trace"][i], segment
        if np.isfinite(table.observed_recurrence[i]):
            assert table.sources["source_observed_recurrence"][i], segment
        if np.isfinite(table.observed_slip[i]):
            assert table.sources["source_observed_slip"][i], segment
    carrizo = table.ids.index("carrizo")
    assert table.slip_rate[carrizo] == pytest.approx(33.9e-3 / YEAR)
    assert table.observed_recurrence[carrizo] == pytest.approx(88 * YEAR)


def test_per_segment_predictions_follow_the_seed_scaling(bundled):
    spec, ds = bundled
    carrizo = ds.sel(segment="carrizo")
    # granodiorite at tau = 250 bar, D = 13 mi: the 1906 slip, independent of slip rate at these rates
    assert float(carrizo["slip_per_event"]) == pytest.approx(6.4374, rel=1e-4)
    assert float(carrizo["recurrence_period"]) == pytest.approx(6.4374 / (33.9e-3 / YEAR), rel=1e-4)
    length = float(carrizo["segment_length"])
    assert 140e3 < length < 180e3
    moment = 0.25e11 * length * 12e3 * float(carrizo["slip_per_event"])
    assert float(carrizo["moment_magnitude"]) == pytest.approx(2 / 3 * (np.log10(moment) - 9.1), rel=1e-12)
    creeping = ds.sel(segment="creeping")
    # green schist slides steadily in the lab (mu_so = mu_m): fault refuses it, so the map flags it
    assert int(creeping["outside_domain"]) == 1 and int(creeping["regime"]) == -1
    assert np.isnan(float(creeping["slip_per_event"]))


def test_predicted_against_observed_is_reported_as_it_is(bundled):
    _, ds = bundled
    table = observed_table(ds)
    assert "| carrizo |" in table and "| parkfield |" in table
    ratio = float(ds["recurrence_ratio"].sel(segment="carrizo"))
    assert ratio == pytest.approx((6.4374 / (33.9e-3 / YEAR)) / (88 * YEAR), rel=1e-4)  # ~2.2: over-predicted
    assert float(ds["slip_ratio"].sel(segment="north_coast")) == pytest.approx(6.4374 / 6.4, rel=1e-4)


def test_nearest_segment_raster(bundled):
    spec, ds = bundled
    index = ds["nearest_segment"]
    assert index.dims == ("lat", "lon") and (index.values >= 0).any() and (index.values == -1).any()
    # a cell on the Carrizo trace belongs to Carrizo, at near-zero distance
    i, j = np.abs(ds["lat"].values - 35.40).argmin(), np.abs(ds["lon"].values - (-119.97)).argmin()
    assert ds["segment"].values[int(index.values[i, j])] == "carrizo"
    assert float(ds["distance_to_segment"].values[i, j]) < 8e3
    assert np.isnan(ds["map_slip_per_event"].values[index.values == -1]).all()


def test_geodesy_against_known_distances():
    # one degree of latitude on WGS84 near 35 N is 110.95 km
    assert trace_length(np.array([[-120.0, 34.5], [-120.0, 35.5]])) == pytest.approx(110.95e3, rel=1e-3)
    index, distance = nearest_segment(np.array([-120.0]), np.array([36.0]), [np.array([[-119.0, 35.0], [-119.0, 37.0]])])
    assert distance[0, 0] == pytest.approx(90.1e3, rel=1e-2)  # 1 degree of longitude at 36 N


def test_map_cli_writes_netcdf_and_plots(cli, tmp_path):
    result = cli("map", "san_andreas_map.toml", "-o", tmp_path / "m.nc", "--plot", tmp_path / "m.png", "--json")
    assert result.code == 0, result.err
    data = result.json
    carrizo = next(row for row in data["segments"] if row["segment"] == "carrizo")
    assert carrizo["slip_per_event"]["units"] == "m" and carrizo["recurrence_ratio"] > 1
    assert (tmp_path / "m_observed.png").exists() and (tmp_path / "m.png").exists()
    with xr.open_dataset(tmp_path / "m.nc") as ds:
        assert ds["map_recurrence_period"].attrs["units"] == "s" and ds["lat"].attrs["units"] == "degrees_north"


def _write_map(tmp_path, table_text=None, raster=None):
    config = tmp_path / "m.toml"
    if table_text is not None:
        (tmp_path / "t.csv").write_text(table_text)
        config.write_text('[map]\nbase = "san_andreas_1906.toml"\n[segments]\nfile = "t.csv"\n'
                          '[grid]\nlon = { linspace = [-121.0, -119.0, 5] }\nlat = { linspace = [35.0, 36.0, 4] }\n')
    else:
        config.write_text(f'[map]\nbase = "san_andreas_1906.toml"\n[raster]\nfile = "{raster}"\n')
    return config


HEADER = "segment,trace (degree),slip_rate (mm/yr),lithology,seismogenic_depth (km),zone_width (km)\n"


def test_raster_inputs_from_netcdf_and_csv(tmp_path):
    lon, lat = np.array([-121.0, -120.0]), np.array([35.0, 36.0])
    raster = xr.Dataset({"lithology": (("lat", "lon"), np.array([["granodiorite", "black_marble"], ["pyrite", "granodiorite"]])),
                         "slip_rate": (("lat", "lon"), np.array([[10.0, 20.0], [30.0, 40.0]]), {"units": "mm/yr"})},
                        coords={"lat": lat, "lon": lon})
    raster.to_netcdf(tmp_path / "r.nc")
    ds = run_map(read_map(_write_map(tmp_path, raster="r.nc")))
    assert ds["slip_per_event"].dims == ("lat", "lon")
    expected = 6.4374 / (40e-3 / YEAR)
    assert float(ds["recurrence_period"].sel(lat=36.0, lon=-120.0)) == pytest.approx(expected, rel=1e-4)
    (tmp_path / "r.csv").write_text("lon (degree),lat (degree),lithology,slip_rate (mm/yr)\n"
                                    "-121,35,granodiorite,10\n-120,35,black_marble,20\n-121,36,pyrite,30\n-120,36,granodiorite,40\n")
    from_csv = run_map(read_map(_write_map(tmp_path, raster="r.csv")))
    np.testing.assert_allclose(from_csv["slip_per_event"].values, ds["slip_per_event"].values)


@pytest.mark.parametrize("row, message", [
    ("a,-120 35,30,granodiorite,12,20\n", "row 2, trace: a segment trace needs at least 2 vertices"),
    ("a,-120 35; -200 36,30,granodiorite,12,20\n", "longitude -200 is out of range"),
    ("a,-120 35; -120 96,30,granodiorite,12,20\n", "latitude 96 is out of range"),
    ("a,-120 35; -120 36,30,granodorite,12,20\n", "row 2: unknown lithology"),
    ("a,-120 35; -120 36,fast,granodiorite,12,20\n", "row 2, slip_rate"),
    ("a,-120 35; -120 36,30,granodiorite\n", "row 2: 4 fields, expected 6"),
])
def test_bad_segment_tables_name_file_and_row(tmp_path, row, message):
    config = _write_map(tmp_path, HEADER + row)
    with pytest.raises(InputError, match=message):
        read_map(config)


def test_bad_inputs_via_cli_exit_2_and_write_nothing(cli, tmp_path):
    config = _write_map(tmp_path, HEADER + "a,-120 35,30,granodiorite,12,20\n")
    result = cli("map", config, "-o", tmp_path / "out.nc")
    assert result.code == 2 and "t.csv, row 2" in result.err and "Traceback" not in result.err
    assert not (tmp_path / "out.nc").exists()
    (tmp_path / "broken.nc").write_bytes(b"not a netCDF file")
    result = cli("map", _write_map(tmp_path, raster="broken.nc"), "-o", tmp_path / "out.nc")
    assert result.code == 2 and "broken.nc" in result.err and not (tmp_path / "out.nc").exists()
    bad_units = xr.Dataset({"slip_rate": (("lat", "lon"), np.ones((1, 1)), {"units": "bar"})},
                           coords={"lat": [35.0], "lon": [-120.0]})
    bad_units.to_netcdf(tmp_path / "units.nc")
    result = cli("map", _write_map(tmp_path, raster="units.nc"), "-o", tmp_path / "out.nc")
    assert result.code == 2 and "slip_rate" in result.err and "speed" in result.err


def test_parse_trace_rejects_garbage():
    with pytest.raises(InputError, match="two numbers"):
        parse_trace("-120 x; -121 36", "t")


def test_a_rate_state_map_gives_each_segment_its_faults_cycles(tmp_path):
    """Each segment's slip and recurrence are rate_state_cells on that segment's fault (its lithology's G,
    slip rate, zone width), with Mw from its length; the bundled example runs (configs/)."""
    from faultslip.fault.rate_state_cells import rate_state_cells
    from faultslip.friction.materials import resolve_material

    table = HEADER + ("a,-120.5 35.0; -120.0 35.6,30,granodiorite,12,20\n"
                      "b,-119.5 35.0; -119.2 35.5,10,black_marble,10,15\n")
    config = _write_map(tmp_path, table)
    config.write_text(config.read_text().replace("san_andreas_1906.toml", "san_andreas_1906_rate_state.toml")
                      .replace("[segments]", "cycles = 2\n[segments]"))
    spec = read_map(config)
    ds = run_map(spec)
    assert ds["method"].attrs["flag_meanings"] == "solver_failed closed_form lsoda dopri5 dopri5_compiled"
    # the map's own slip rates: one ulp of input moves the cycles by ~1e-7 (their rtol), so exact inputs
    np.testing.assert_allclose(ds["slip_rate"].values, np.array([30, 10]) * 1e-3 / YEAR, rtol=1e-15)
    for index, (lithology, depth, width) in enumerate([("granodiorite", 12e3, 20e3), ("black_marble", 10e3, 15e3)]):
        one = rate_state_cells(shear_modulus=resolve_material(lithology).shear_modulus, zone_width=width,
                               normal_stress=250e5 / 0.65, plate_rate=float(ds["slip_rate"][index]), a=0.010, b=0.015,
                               critical_slip=0.008, mu0=0.65, cycles=2,
                               rupture_length=float(ds["segment_length"][index]), seismogenic_depth=depth)
        for name in ("slip_per_event", "recurrence_period", "moment_magnitude", "stiffness_ratio", "model_error",
                     "width_over_nucleation", "estimated_relative_error"):
            assert float(ds[name][index]) == pytest.approx(float(one[name]), rel=1e-12), name
    assert np.nanmax(ds["map_slip_per_event"].values) > 0
    bundled = run_map(read_map("san_andreas_map_rate_state.toml"))
    assert np.all(bundled["regime"].values == 0) and np.all(bundled["slip_per_event"].values > 0)
    # each segment is one block standing for a fault: its table reads the model error as the 2-D fault's range
    table = observed_table(bundled).splitlines()
    assert table[0].endswith("| 2-D fault's recurrence by the model error (yr) |") and table[1].count("---") == 9
    for row, line in zip(segment_rows(bundled), table[2:]):
        low = row["recurrence_period"] / (1 + row["model_error"]) / YEAR
        high = "no upper end" if row["model_error"] >= 1 else f"{row['recurrence_period'] / (1 - row['model_error']) / YEAR:.3g}"
        assert line.endswith(f"| {low:.3g} to {high} |"), line
    assert "model error" not in observed_table(run_map(read_map("san_andreas_map.toml")))  # the seed law declares none


@pytest.mark.parametrize("head, message", [
    ('base = "san_andreas_1906_rate_state.toml"\ncycles = 0', "cycles in m.toml must be a whole number from 1"),
    ('base = "san_andreas_1906_rate_state.toml"\nmethod = "closed_form"', "method in m.toml must be one of auto"),
    ('base = "san_andreas_1906.toml"\ncycles = 3', "apply to a base scene with rate-and-state friction"),
])
def test_rate_state_map_options_are_checked(tmp_path, head, message):
    config = _write_map(tmp_path, HEADER + "a,-120.5 35.0; -120.0 35.6,30,granodiorite,12,20\n")
    config.write_text(config.read_text().replace('base = "san_andreas_1906.toml"', head))
    with pytest.raises(InputError, match=message):
        read_map(config)


def _rate_state_raster_map(folder, size: int, cycles: int = 5):
    """A rate-and-state map of a size x size raster, every cell the same fault but its slip rate."""
    lon, lat = np.linspace(-122.0, -118.0, size), np.linspace(34.0, 37.0, size)
    raster = xr.Dataset({"slip_rate": (("lat", "lon"), np.linspace(10.0, 40.0, size * size).reshape(size, size),
                                       {"units": "mm/yr"}),
                         "shear_modulus": (("lat", "lon"), np.full((size, size), 30.0), {"units": "GPa"})},
                        coords={"lat": lat, "lon": lon})
    raster.to_netcdf(folder / f"r{size}.nc")
    config = folder / f"m{size}_{cycles}.toml"
    config.write_text(f'[map]\nbase = "san_andreas_1906_rate_state.toml"\ncycles = {cycles}\n[raster]\n'
                      f'file = "r{size}.nc"\n', encoding="utf-8")
    return config


def test_a_rate_state_maps_estimate_counts_the_cycles_in_every_cell(cli, tmp_path, monkeypatch):
    """A rate-and-state raster map runs its cycles in every unstable cell (about 2 ms each with the C stepper):
    its budget had counted the raster's nearest-distance work alone (5 ms for 10,000 cells whose run took 22 s
    of CPU), so a raster of millions of cells ran for hours unrefused. The estimate now adds the cycles, by the
    rate-and-state cells' shared cost model over the map's own K / K_c, and 'faultslip map --estimate' prints it."""
    from faultslip.fault.rate_state_cells import estimated_seconds
    from faultslip.io import budget
    from faultslip.studies.maps import map_size_estimate

    small = read_map(_rate_state_raster_map(tmp_path, 6))
    ran = run_map(small)
    raster_seconds = 36 / budget.MAP_CELLS_PER_SECOND
    cycles_seconds = estimated_seconds(ran["stiffness_ratio"].values.ravel(), 0.010 / 0.015, 5, 1e-6, "auto")
    assert cycles_seconds > 100 * raster_seconds
    # each against its cost model's seconds, without what the map imports (measured, apart)
    assert map_size_estimate(small).modelled_seconds == pytest.approx(raster_seconds + cycles_seconds, rel=1e-9)
    # the cells are the same fault: four times the cells, four times the cycles; more cycles cost more
    large = read_map(_rate_state_raster_map(tmp_path, 12))
    assert map_size_estimate(large).modelled_seconds == pytest.approx(4 * (raster_seconds + cycles_seconds), rel=1e-9)
    # a raster wider than the cost model's sample (64 a side) is read on a strided sample of its cells
    wide = read_map(_rate_state_raster_map(tmp_path, 70))
    assert map_size_estimate(wide).modelled_seconds == pytest.approx(4900 / 36 * (raster_seconds + cycles_seconds),
                                                                     rel=1e-9)
    longer = estimated_seconds(ran["stiffness_ratio"].values.ravel(), 0.010 / 0.015, 10, 1e-6, "auto")
    assert longer > cycles_seconds and map_size_estimate(read_map(_rate_state_raster_map(
        tmp_path, 6, cycles=10))).modelled_seconds == pytest.approx(raster_seconds + longer, rel=1e-9)
    # the command prints it, needing no output and writing nothing; over the budget, the map is refused first
    printed = cli("map", tmp_path / "m12_5.toml", "--estimate", "--json")
    assert printed.code == 0 and modelled_seconds(printed.json) == pytest.approx(
        map_size_estimate(large).modelled_seconds, rel=1e-9) and "rate-and-state cycles" in printed.json["what"]
    import faultslip  # and a notebook asks the same of the file

    assert faultslip.hazard.map_estimate(tmp_path / "m12_5.toml").modelled_seconds == pytest.approx(
        map_size_estimate(large).modelled_seconds, rel=1e-12)
    monkeypatch.setenv("FAULTSLIP_TIME_BUDGET", str(map_size_estimate(large).modelled_seconds / 2))
    assert_clean_error(cli("map", tmp_path / "m12_5.toml", "-o", tmp_path / "out.nc"), "--allow-large")
    assert not (tmp_path / "out.nc").exists()
