"""Fault-displacement hazard (issue 44, item 5): a single rupture by hand, the profile's calibration to faultslip's
slip per event, Petersen et al. (2011) and Wells & Coppersmith (1993) by hand, a fit's draws carried through, the
fault system's ruptures through a site, and refusals.

Provenance: Petersen et al. (2011), BSSA 101(2), 805-825, elliptical ln(D) model for principal displacement
(3.3041, 1.7927, -11.2192, sigma 1.1348); Wells & Coppersmith (1993), SRL 64(1), 54 (-12.51, 2.053). The hand
computations below use math.erfc and Simpson's rule in the angle u = (1 - cos t) / 2, not the module's scipy calls.
"""

import math
from pathlib import Path

import numpy as np
import pytest

from conftest import assert_clean_error
from faultslip.errors import InputError
from faultslip.fault import displacement as fdh
from faultslip.io.geo import trace_length

ROOT = Path(__file__).resolve().parents[3]
MAP = ROOT / "configs" / "california_faults_map.toml"
SYSTEM = ROOT / "configs" / "california_fault_system.toml"
YEAR = 365.25 * 86400


def _mean_shape_by_hand(b=3.3041, points=20001):
    """<e^{b x*}> over x/L in [0, 1]: with x/L = (1 - cos t) / 2, x* = sin t and d(x/L) = sin(t) / 2 dt, a smooth
    integrand Simpson's rule takes to round-off."""
    t = np.linspace(0.0, math.pi, points)
    f = np.exp(b * np.sin(t)) * np.sin(t) / 2
    h = t[1] - t[0]
    return h / 3 * (f[0] + f[-1] + 4 * f[1:-1:2].sum() + 2 * f[2:-1:2].sum())


def _exceed(d, median, sigma):
    return 0.5 * math.erfc((math.log(d) - math.log(median)) / (sigma * math.sqrt(2)))


def test_petersen_and_wells_coppersmith_by_hand():
    mean_log, sigma = fdh.petersen_2011(7.0, 0.5)
    assert math.exp(mean_log) == pytest.approx(math.exp(3.3041 + 1.7927 * 7 - 11.2192) / 100, rel=1e-13)
    assert sigma == 1.1348
    # at the rupture's ends x* = 0
    assert math.exp(fdh.petersen_2011(7.0, 0.0)[0]) == pytest.approx(math.exp(1.7927 * 7 - 11.2192) / 100, rel=1e-13)
    assert fdh.surface_rupture_probability(12.51 / 2.053) == pytest.approx(0.5, abs=1e-15)
    m = 6.5
    assert fdh.surface_rupture_probability(m) == pytest.approx(1 / (1 + math.exp(12.51 - 2.053 * m)), rel=1e-14)
    assert fdh._mean_shape() == pytest.approx(_mean_shape_by_hand(), rel=1e-12)


def test_the_faultslip_profile_averages_to_the_slip_per_event():
    """The mean over the rupture of the expected displacement E[D(x)] = exp(mu + sigma^2 / 2) is faultslip's AD."""
    t = np.linspace(0.0, math.pi, 20001)
    x = (1 - np.cos(t)) / 2
    mean_log, sigma = fdh.faultslip_profile(np.full(x.size, 6.44), x)
    f = np.exp(mean_log + sigma ** 2 / 2) * np.sin(t) / 2
    h = t[1] - t[0]
    average = h / 3 * (f[0] + f[-1] + 4 * f[1:-1:2].sum() + 2 * f[2:-1:2].sum())
    assert average == pytest.approx(6.44, rel=1e-11)


def test_a_single_rupture_by_hand(cli, tmp_path):
    """The bundled California map's Carrizo segment, the site on its middle vertex: one rupture, its rate 1 / T,
    Mw and slip per event from the map, x / L the trace's length to the vertex over its whole length."""
    out = cli("map", MAP, "-o", tmp_path / "m.nc", "--displacement-hazard", "-119.5 35.05", "--displacements",
              "0.1 m, 1 m, 300 cm, 10 m, 20 m", "--json")
    assert out.code == 0, out.err
    result = out.json["displacement_hazard"]
    assert result["fault"] == "SA-CAR" and result["ruptures"] == 1 and result["distance_to_trace"]["value"] < 1.0
    row = next(r for r in out.json["segments"] if r["segment"] == "SA-CAR")
    rate = YEAR / row["recurrence_period"]["value"]
    magnitude, average = row["moment_magnitude"], row["slip_per_event"]["value"]
    trace = np.array([[-120.29, 35.74], [-119.5, 35.05], [-118.90, 34.80]])
    x = trace_length(trace[:2]) / trace_length(trace)
    x_star = math.sqrt(1 - (x - 0.5) ** 2 / 0.25)
    sigma = 1.1348
    median = average * math.exp(3.3041 * x_star) / _mean_shape_by_hand() * math.exp(-sigma ** 2 / 2)
    surface = 1 / (1 + math.exp(12.51 - 2.053 * magnitude))
    expected = [rate * surface * _exceed(d, median, sigma) for d in (0.1, 1.0, 3.0, 10.0, 20.0)]
    np.testing.assert_allclose(result["annual_exceedance_rate"]["value"], expected, rtol=1e-9)
    assert result["displacement"]["value"] == pytest.approx([0.1, 1.0, 3.0, 10.0, 20.0])
    # Petersen's own level, from Mw
    out = cli("map", MAP, "-o", tmp_path / "p.nc", "--displacement-hazard", "-119.5 35.05", "--displacements", "1 m",
              "--displacement-model", "petersen_2011", "--json")
    median = math.exp(3.3041 * x_star + 1.7927 * magnitude - 11.2192) / 100
    assert out.json["displacement_hazard"]["annual_exceedance_rate"]["value"][0] == pytest.approx(
        rate * surface * _exceed(1.0, median, sigma), rel=1e-9)
    # the curve travels in the map's netCDF on its own dimension
    import xarray as xr

    with xr.open_dataset(tmp_path / "m.nc") as data:
        np.testing.assert_allclose(data["displacement_annual_exceedance_rate"].values, expected, rtol=1e-9)
        assert data["displacement"].attrs["units"] == "m"


def test_the_fault_systems_ruptures_through_the_site(tmp_path):
    """With a [rupture_set], the ruptures through the site's section are the system's: their rates add up to the
    section's participation rate, and each places the site inside it."""
    from faultslip.studies import displacement_hazard as dh
    from faultslip.studies import rupture_sets as rs
    from faultslip.studies.maps import read_map, run_map

    spec = read_map(SYSTEM)
    dataset = run_map(spec)
    system = rs.rupture_set(spec, dataset, spec.rupture_rules, "faultslip")
    site = (-119.5, 35.05)
    ruptures = dh._system_ruptures(system, *site)
    section = system.sections.ids.index(ruptures["name"])
    assert ruptures["rates"].sum() == pytest.approx(system.participation[section], rel=1e-12)
    assert np.all((ruptures["positions"] >= 0) & (ruptures["positions"] <= 1))
    curve = dh.displacement_hazard(spec, dataset, site, system=system, displacements=[1e-3])
    surface = fdh.surface_rupture_probability(ruptures["magnitudes"])
    # a millimetre is exceeded by nearly every rupture that reaches the surface
    assert curve.rate[0] == pytest.approx(float(np.sum(ruptures["rates"] * surface)), rel=1e-3)


def test_a_fits_draws_are_carried_through(tmp_path, cli, monkeypatch):
    """A segment whose lithology is a saved fit: each bootstrap sample's slip per event scales the rupture, and the
    curve is their mean with percentiles that bracket it."""
    from faultslip.friction.fitting import synthetic_data
    from faultslip.friction.materials import get_preset

    monkeypatch.setenv("FAULTSLIP_REGISTRY", str(tmp_path / "fits.json"))
    preset = get_preset("granodiorite_water")
    data = synthetic_data(preset, points=30, noise=0.003, seed=7, amplitude_noise=2e-6)
    lines = ["loading_rate (1/s),static_friction,amplitude (m),normal_load (lbf),stiffness (lbf/in)"]
    lines += [f"{r!r},{m!r},{a!r},169.9,19400" for r, m, a in zip(data.loading_rate.tolist(),
                                                                 data.static_friction.tolist(), data.amplitude.tolist())]
    (tmp_path / "gouge.csv").write_text("\n".join(lines) + "\n", encoding="utf-8")
    fitted = cli("fit", tmp_path / "gouge.csv", "--name", "my_gouge", "--shear-modulus", "0.25e6 bar", "--bootstrap",
                 "40")
    assert fitted.code == 0, fitted.err
    table = (ROOT / "data" / "san_andreas_segments.csv").read_text(encoding="utf-8").splitlines()
    header, carrizo = table[0], next(line for line in table if line.startswith("carrizo"))
    (tmp_path / "segments.csv").write_text(header + "\n" + carrizo.replace(",granodiorite,", ",my_gouge,") + "\n",
                                           encoding="utf-8")
    text = (ROOT / "configs" / "san_andreas_map.toml").read_text(encoding="utf-8")
    text = text.replace('file = "../data/san_andreas_segments.csv"', 'file = "segments.csv"').replace(
        'base = "san_andreas_1906.toml"', f'base = "{ROOT / "configs" / "san_andreas_1906.toml"}"')
    (tmp_path / "map.toml").write_text(text, encoding="utf-8")
    trace = carrizo.split(",")[2].split(";")[1].split()
    out = cli("map", tmp_path / "map.toml", "-o", tmp_path / "m.nc", "--displacement-hazard", " ".join(trace),
              "--plot", tmp_path / "m.png", "--json")
    assert out.code == 0, out.err
    result = out.json["displacement_hazard"]
    assert result["draws"] == 40 and set(result["quantiles"]) == {"5", "16", "50", "84", "95"}
    mean = np.array(result["annual_exceedance_rate"]["value"])
    low, high = (np.array(result["quantiles"][q]["value"]) for q in ("5", "95"))
    middle = slice(10, 35)  # where the draws spread the curve (below 1 m every rupture exceeds)
    assert np.all(low[middle] <= mean[middle]) and np.all(mean[middle] <= high[middle])
    assert np.any(high[middle] > low[middle] * 1.01)
    assert (tmp_path / "m_displacement.png").exists()


@pytest.mark.parametrize("extra, message", [
    (("--displacement-hazard", "-121 35"), "from the nearest fault trace"),
    (("--displacement-hazard", "-120 36; -119 35"), "one site"),
    (("--displacement-hazard", "-119.5 35.05", "--displacement-model", "boore"), "--displacement-model"),
    (("--displacement-model", "petersen_2011"), "give --displacement-hazard"),
    (("--displacements", "1 m"), "give --displacement-hazard"),
    (("--displacement-hazard", "-119.5 35.05", "--displacements", "-1 m"), "--displacements"),
    (("--displacement-hazard", "-119.5 35.05", "--displacements", "1 kg"), "--displacements"),
    (("--displacement-hazard", "west 35.28"), "longitude latitude"),
])
def test_bad_displacement_options_are_one_sentence(cli, tmp_path, extra, message):
    out = cli("map", MAP, "-o", tmp_path / "m.nc", *extra)
    assert_clean_error(out, message)
    assert not (tmp_path / "m.nc").exists()


def test_refusals_in_python():
    with pytest.raises(InputError, match="from 0 to 1"):
        fdh.elliptical_position(1.2)
    with pytest.raises(InputError, match="average displacement"):
        fdh.displacement_hazard_curve([1.0], [0.01], [7.0], [0.5])
    with pytest.raises(InputError, match="model"):
        fdh.displacement_hazard_curve([1.0], [0.01], [7.0], [0.5], [1.0], model="x")


# --- the fault map a hazard analyst reads (issue 44, item 6) -----------------------------------------------

def _map_dataset():
    from faultslip.studies.maps import read_map, run_map

    return run_map(read_map(MAP))


def test_the_fault_map_is_projected_with_coastlines_and_colours_each_trace_by_its_value():
    pytest.importorskip("mpl_toolkits.basemap", reason="the maps extra (basemap) is not installed")
    from matplotlib.collections import LineCollection

    from faultslip.plots.fault_maps import fault_system_figure

    dataset = _map_dataset()
    figure = fault_system_figure(dataset, resolution="c")
    panels = [axes for axes in figure.axes if axes.get_title()]
    assert len(panels) == 4
    slip_rate = panels[0]
    traces = [c for c in slip_rate.collections if isinstance(c, LineCollection) and c.get_array() is not None]
    assert len(traces) == 1
    np.testing.assert_allclose(traces[0].get_array(), dataset["slip_rate"].values * YEAR * 1e3, rtol=1e-12)
    # projected: Lambert conformal metres, not degrees; and the coastline is drawn beneath
    x = np.concatenate([segment[:, 0] for segment in traces[0].get_segments()])
    assert x.min() > 1e4
    assert len(slip_rate.collections) > 3  # coastlines, countries, states and the continents' fill
    # a field the map computed to one value is said in words, with no colour bar, not a range of round-off
    assert "on every fault" in panels[1].get_title()
    assert any(text.get_text().startswith("all ") and "the same on every fault" in text.get_text()
               for text in panels[1].texts)
    assert len([axes for axes in figure.axes if not axes.get_title()]) == 3  # three colour bars, not four
    # every fault is named on the first panel, and the colour maps' palest tenth is left out (visible on land)
    names = {text.get_text() for text in slip_rate.texts}
    assert {name.replace("_", " ") for name in dataset["segment"].values} <= names
    recurrence_colours = [c for c in panels[2].collections if isinstance(c, LineCollection)
                          and c.get_array() is not None][0].get_cmap()
    lowest = np.asarray(recurrence_colours(0.0)[:3])
    assert lowest @ np.array([0.299, 0.587, 0.114]) < 0.9  # magma_r's own low end is 0.96, nearly white
    participation = [c for c in panels[3].collections if isinstance(c, LineCollection) and c.get_array() is not None]
    np.testing.assert_allclose(participation[0].get_array(), YEAR / dataset["recurrence_period"].values, rtol=1e-12)


def test_without_basemap_the_fault_map_says_so(monkeypatch):
    import builtins

    from faultslip.plots.fault_maps import fault_system_figure

    real = builtins.__import__

    def no_basemap(name, *args, **kwargs):
        if name.startswith("mpl_toolkits.basemap"):
            raise ImportError("no basemap")
        return real(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_basemap)
    figure = fault_system_figure(_map_dataset())
    assert "install faultslip[maps]" in figure._suptitle.get_text()
    assert all(len(line) <= 90 for line in figure._suptitle.get_text().splitlines())  # wrapped, never clipped
    assert figure.axes[0].get_xlabel() == "longitude (°E)"


def test_dipping_traces_carry_a_tick_towards_their_dip(tmp_path):
    """A thrust dipping 30 degrees and a normal fault dipping 60, their traces given with the fault to the right
    (Aki & Richards): each trace carries a tick from its middle to its right, labelled with its dip; a vertical
    trace carries none."""
    from faultslip.plots.fault_maps import dip_ticks, fault_system_figure
    from faultslip.studies.maps import read_map, run_map

    east = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])  # a trace striking east dips to the south
    north = np.array([[0.0, 0.0], [0.0, 1.0]])  # striking north: dips to the east
    ticks = dip_ticks([east, north, east], np.array([30.0, 60.0, 90.0]), lambda x, y: (x, y), 0.1)
    assert len(ticks) == 2
    (x0, y0, x1, y1, dip), (u0, v0, u1, v1, dip2) = ticks
    assert (x1 - x0, y1 - y0, dip) == pytest.approx((0.0, -0.1, 30.0))
    assert (u1 - u0, v1 - v0, dip2) == pytest.approx((0.1, 0.0, 60.0))
    from test_dipping_faults import ROWS, _map as dipping_map

    lines = ROWS.splitlines(keepends=True)  # the 30-degree thrust and the vertical fault
    dipping_map(tmp_path, rows=lines[0] + lines[2])
    figure = fault_system_figure(run_map(read_map(tmp_path / "map.toml")), resolution="c")
    labels = [text.get_text() for text in figure.axes[0].texts]
    assert "30°" in labels and "90°" not in labels
