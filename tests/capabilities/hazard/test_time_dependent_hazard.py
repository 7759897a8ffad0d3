"""Time-dependent sources (issue 44, item 4): a renewal model with the time since the last rupture becomes the
probability of a rupture in the investigation time, written as non-parametric sources the engine runs, with the
Poissonian branch beside them."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from conftest import engine_command, run_engine_job
from faultslip.errors import InputError
from faultslip.fault.recurrence import conditional_probability, distribution
from faultslip.io.nrml import occurrence_probabilities
from faultslip.studies import hazard
from faultslip.studies.maps import read_map, run_map
from faultslip.units import JULIAN_YEAR as YEAR

NS = {"n": "http://openquake.org/xmlns/nrml/0.5"}
MAP = "configs/san_andreas_map.toml"


@pytest.fixture(scope="module")
def sources():
    spec = read_map(MAP)
    return hazard.hazard_sources(spec, run_map(spec))


def _elapsed(sources, years=100.0):
    return {source.id: years * YEAR * (1 + 0.1 * k) for k, source in enumerate(sources) if source.has_event}


def test_a_sources_probability_is_the_renewal_models_conditional_probability(sources, tmp_path):
    elapsed = _elapsed(sources)
    made = hazard.time_dependent_sources(sources, elapsed, "bpt", 0.5, 50 * YEAR)
    assert len(made) == len(elapsed)
    out = hazard.write_time_dependent_model(tmp_path / "td.xml", made, "San Andreas")
    written = {node.get("id"): node for node in ET.parse(tmp_path / "td_bpt.xml").getroot().iter(
        "{http://openquake.org/xmlns/nrml/0.5}nonParametricSeismicSource")}
    for source in made:
        # by hand: (F(e + t) - F(e)) / (1 - F(e)) of the BPT law with faultslip's recurrence as its mean
        law = distribution("bpt", source.source.recurrence, 0.5)
        e, t = source.elapsed, 50 * YEAR
        by_hand = (law.cdf(e + t) - law.cdf(e)) / law.sf(e)
        assert source.probability == pytest.approx(by_hand, rel=1e-9, abs=1e-12)
        assert source.probability == conditional_probability("bpt", source.source.recurrence, 0.5, e, t)
        none, one = (float(v) for v in written[source.source.id].find("n:simpleFaultRupture", NS).get(
            "probs_occur").split())
        assert none + one == 1.0 and abs(one - source.probability) <= 1e-9
        assert source.poisson_probability == pytest.approx(1 - math.exp(-t / source.source.recurrence), rel=1e-12)
    assert set(out["probabilities"]) == {"poisson", "bpt"}
    tree = ET.parse(tmp_path / "td.xml").getroot()
    weights = {b.get("branchID"): float(b.find("n:uncertaintyWeight", NS).text)
               for b in tree.iter("{http://openquake.org/xmlns/nrml/0.5}logicTreeBranch")}
    assert weights == {"poisson": 0.5, "bpt": 0.5}


def test_the_renewal_model_remembers_and_poisson_does_not(sources):
    """Just after a rupture a BPT fault is less likely than Poisson to rupture again; long overdue, more likely."""
    source = next(s for s in sources if s.has_event)
    early = hazard.time_dependent_sources([source], {source.id: 0.05 * source.recurrence}, "bpt", 0.5, 30 * YEAR)[0]
    late = hazard.time_dependent_sources([source], {source.id: 1.5 * source.recurrence}, "bpt", 0.5, 30 * YEAR)[0]
    assert early.probability < early.poisson_probability < late.probability
    lognormal = hazard.time_dependent_sources([source], {source.id: source.recurrence}, "lognormal", 0.5, 30 * YEAR)
    assert 0 < lognormal[0].probability < 1


@pytest.mark.parametrize("probability", [0.0, 1e-17, 1e-9, 0.25, 0.5, 0.5 + 1e-16, 0.75, 1 - 1e-12, 1.0])
def test_occurrence_probabilities_sum_to_one_exactly(probability):
    none, one = (float(v) for v in occurrence_probabilities(probability).split())
    assert none + one == 1.0 and abs(one - probability) <= 2.3e-16


def test_bad_renewal_inputs_are_one_sentence(sources):
    elapsed = _elapsed(sources)
    first = next(iter(elapsed))
    for call, words in (
            (lambda: hazard.time_dependent_sources(sources, elapsed, "weibull"), "renewal model"),
            (lambda: hazard.time_dependent_sources(sources, elapsed, "bpt", 0.0), "aperiodicity"),
            (lambda: hazard.time_dependent_sources(sources, elapsed, "bpt", 0.5, -1.0), "investigation time"),
            (lambda: hazard.time_dependent_sources(sources, {**elapsed, first: -5.0}), "zero or positive"),
            (lambda: hazard.time_dependent_sources(sources, {**elapsed, "XX": 1.0}), "no segment 'XX'"),
            (lambda: hazard.time_dependent_sources(sources, {}), "no time since its last rupture"),
            (lambda: occurrence_probabilities(1.5), "from 0 to 1")):
        with pytest.raises(InputError, match=words) as caught:
            call()
        assert "\n" not in str(caught.value)
    made = hazard.time_dependent_sources(sources, elapsed)
    with pytest.raises(InputError, match="weight"):
        hazard.write_time_dependent_model("td.xml", made, "x", renewal_weight=1.0)


def test_the_engine_parses_and_runs_the_time_dependent_model(sources, tmp_path):
    """The engine's own parser reads both branches, each source's rupture with its probability; a classical PSHA
    runs on the logic tree, and its curve stays below what the branches' ruptures allow:
    P(exceeded) <= 1 - prod(1 - P_i) on the larger branch."""
    nrml = pytest.importorskip("openquake.hazardlib.nrml", reason="the OpenQuake engine is not installed")
    from openquake.hazardlib.sourceconverter import SourceConverter

    made = hazard.time_dependent_sources(sources, _elapsed(sources), "bpt", 0.5, 50 * YEAR)
    hazard.write_time_dependent_model(tmp_path / "td.xml", made, "San Andreas")
    converter = SourceConverter(investigation_time=50.0, rupture_mesh_spacing=2.0, width_of_mfd_bin=0.1)
    for branch in ("poisson", "bpt"):
        model = nrml.to_python(str(tmp_path / f"td_{branch}.xml"), converter)
        parsed = {source.source_id: source for group in model for source in group}
        assert len(parsed) == len(made)
        for source in made:
            rupture, pmf = parsed[source.source.id].data[0]
            expected = source.probability if branch == "bpt" else source.poisson_probability
            assert abs(dict((value, prob) for prob, value in pmf.data)[1] - expected) <= 1e-9
            assert rupture.mag == pytest.approx(source.source.magnitude, abs=1e-9)
    engine_command()
    hazard.write_engine_job(tmp_path / "job.ini", str(tmp_path / "td.xml"), True, [(-120.43, 35.87)],
                            investigation_time=50.0)
    lines = run_engine_job(tmp_path / "job.ini", tmp_path)
    poes = np.array([float(v) for v in lines[2].split(",")[3:]])
    bound = max(1 - np.prod([1 - s.probability for s in made]), 1 - np.prod([1 - s.poisson_probability for s in made]))
    assert np.all(np.diff(poes) <= 1e-12) and 0 < poes[0] <= bound + 1e-9


LAST = ("north_coast=1906.3; peninsula=1906.3; santa_cruz_mountains=1989.8; parkfield=2004.74; carrizo=1857.02; "
        "mojave=1857.02; san_bernardino=1812.9; coachella=1690; hayward=1868.8")


def test_the_map_command_writes_them_and_refuses_what_does_not_fit(cli, sources, tmp_path):
    from conftest import assert_clean_error

    out = cli("map", MAP, "-o", tmp_path / "m.nc", "--time-dependent", tmp_path / "td.xml", "--renewal",
              "lognormal:0.6", "--forecast-year", "2026", "--investigation-time", "30 yr", "--last-ruptures", LAST,
              "--json")
    assert out.code == 0, out.err
    rows = {row["id"]: row for row in out.json["hazard"]["time_dependent"]}
    last = dict(part.strip().split("=") for part in LAST.split(";"))
    for source in sources:
        if not source.has_event:
            continue
        expected = conditional_probability("lognormal", source.recurrence, 0.6,
                                           (2026 - float(last[source.id])) * YEAR, 30 * YEAR)
        assert rows[source.id]["probability"] == pytest.approx(expected, rel=1e-12)
    assert sorted(p.name for p in tmp_path.glob("td*.xml")) == ["td.xml", "td_lognormal.xml", "td_poisson.xml"]
    base = ["map", MAP, "-o", tmp_path / "n.nc"]
    for extra, words in ((["--last-ruptures", "parkfield=2004"], "give --time-dependent"),
                         (["--time-dependent", tmp_path / "x.xml"], "needs each segment's last rupture"),
                         (["--time-dependent", tmp_path / "x.xml", "--last-ruptures", "parkfield"], "SEGMENT=YEAR"),
                         (["--time-dependent", tmp_path / "x.xml", "--last-ruptures", LAST, "--renewal", "weibull:1"],
                          "--renewal"),
                         (["--time-dependent", tmp_path / "x.xml", "--last-ruptures", LAST + "; nowhere=1900"],
                          "no segment 'nowhere'"),
                         (["--time-dependent", tmp_path / "x.xml", "--last-ruptures", "parkfield=2030",
                           "--forecast-year", "2026"], "after the forecast year")):
        assert_clean_error(cli(*base, *extra), words)
    assert not (tmp_path / "n.nc").exists() and not (tmp_path / "x.xml").exists()


def test_the_map_commands_engine_job_runs_the_time_dependent_model(cli, tmp_path):
    """Without --nrml, --engine-job runs the time-dependent logic tree over its own investigation time."""
    engine_command()
    out = cli("map", MAP, "-o", tmp_path / "m.nc", "--time-dependent", tmp_path / "td.xml", "--last-ruptures", LAST,
              "--forecast-year", "2026", "--investigation-time", "30 yr", "--engine-job", tmp_path / "job.ini",
              "--sites", "-120.43 35.87", "--json")
    assert out.code == 0, out.err
    assert "investigation_time = 30" in (tmp_path / "job.ini").read_text()
    run_engine_job(tmp_path / "job.ini", tmp_path)
    from conftest import assert_clean_error

    assert_clean_error(cli("map", MAP, "-o", tmp_path / "n.nc", "--time-dependent", tmp_path / "x.xml",
                           "--last-ruptures", LAST, "--engine-job", tmp_path / "j.ini"), "go together")
