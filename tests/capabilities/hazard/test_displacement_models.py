"""The field's fault-displacement models beside faultslip's own (issue 73, item 2): fdhpy's seven through one
function, each against fdhpy's own expected results; faultslip's Petersen et al. (2011) against fdhpy's,
computed independently; the style of faulting from the rake; and the models' spread as a logic tree.

tests/data/fdhpy/ holds fdhpy's expected-result files (github.com/asarmy/fdhpy, tests/expected/ at commit cbef812,
MIT licence in the folder): the values its authors computed from each model's published implementation. faultslip
does not implement these models; it calls fdhpy, and these files check that it calls each as the model's authors
meant (the metric, the version, the style, x/L).
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

from conftest import assert_clean_error
from faultslip.errors import InputError
from faultslip.fault import displacement as fdh
from faultslip.studies import displacement_hazard as dh
from faultslip.studies.maps import read_map, run_map

pytest.importorskip("fdhpy")

ROOT = Path(__file__).resolve().parents[3]
EXPECTED = Path(__file__).resolve().parents[2] / "data" / "fdhpy"
#: (model, file, style and its column, or one column for every row's own magnitude and x/L)
CASES = [
    ("youngs_2003", "youngs_2003_prob_exceed_d_ad", {"normal": "probexceed_with_full_aleatory"}, None),
    ("moss_ross_2011", "moss_2011_prob_exceed_d_ad", {"reverse": "probexceed_with_full_aleatory"}, None),
    ("petersen_2011_fdhpy", "petersen_2011_prob_exceed_elliptical", {"strike-slip": "probexceed"}, None),
    ("chiou_2025", "chiou_2025_prob_exceed_model7", {"strike-slip": "prob_exceed"}, None),
    ("moss_2024", "moss_2024_prob_exceed_d_ad_eqs", {"reverse": "probexceed_with_full_aleatory"}, None),
    ("kuehn_2024", "kuehn_2024_prob_exceed_median_coeffs_folded_mag_7p6_xl_0p7",
     {"normal": "normal", "reverse": "reverse", "strike-slip": "strike_slip"}, (7.6, 0.7)),
    ("lavrentiadis_abrahamson_2023", "lavrentiadis_2023_prob_exceed_full_rupure_aggregate_with_pr_zero_mag_7p0_xl_0p6",
     {"normal": "normal", "reverse": "reverse", "strike-slip": "strike_slip"}, (7.0, 0.6)),
]


@pytest.mark.parametrize("model, name, columns, scenario", CASES, ids=[case[0] for case in CASES])
def test_each_fdhpy_model_gives_its_authors_expected_results(model, name, columns, scenario):
    with (EXPECTED / f"{name}.csv").open(encoding="utf-8") as stream:
        rows = list(csv.DictReader(stream))
    assert rows
    for style, column in columns.items():
        groups = {}
        for row in rows:
            key = scenario or (float(row["magnitude"]), float(row["x_l"]))
            groups.setdefault(key, []).append(row)
        for (magnitude, position), group in groups.items():
            d = np.array([float(row["displacement"]) for row in group])
            expected = np.array([float(row[column]) for row in group])
            computed, notes = fdh.fdhpy_exceedance(model, d, [magnitude], [position], style)
            np.testing.assert_allclose(computed[0], expected, rtol=0, atol=1e-6)


def test_faultslips_petersen_2011_is_fdhpys_computed_independently():
    magnitudes, positions = np.array([6.2, 6.8, 7.3, 7.9]), np.array([0.05, 0.5, 0.72, 0.97])
    d = np.logspace(-2, 1.2, 15)
    mean, sigma = fdh.petersen_2011(magnitudes, positions)
    ours = fdh.exceedance_probability(d, mean[:, None], sigma)
    theirs, _ = fdh.fdhpy_exceedance("petersen_2011_fdhpy", d, magnitudes, positions, "strike-slip")
    np.testing.assert_allclose(ours, theirs, rtol=1e-9, atol=1e-15)


@pytest.mark.parametrize("rake, style", [(180.0, "strike-slip"), (0.0, "strike-slip"), (-170.0, "strike-slip"),
                                         (90.0, "reverse"), (45.0, "reverse"), (135.0, "reverse"),
                                         (-90.0, "normal"), (-60.0, "normal"), (270.0, "normal"), (30.0, "strike-slip")])
def test_the_style_of_faulting_comes_from_the_rake(rake, style):
    assert fdh.style_of(rake) == style


def test_a_model_on_a_style_it_was_not_regressed_on_is_refused_naming_those_that_apply():
    with pytest.raises(InputError, match=r"regressed on normal ruptures, not reverse; for reverse: faultslip, "
                                         r"moss_ross_2011"):
        fdh.fdhpy_exceedance("youngs_2003", [1.0], [7.0], [0.5], "reverse")


def _map(tmp_path):
    """A 30-degree thrust (rake 90) and a 60-degree normal fault (rake -90): test_dipping_faults's map."""
    from test_dipping_faults import ROWS, _map as dipping_map

    return dipping_map(tmp_path, rows="".join(ROWS.splitlines(keepends=True)[:2]))

def test_the_logic_tree_is_the_mean_of_every_model_that_applies(tmp_path):
    spec = read_map(_map(tmp_path))
    data = run_map(spec)
    site = (-117.0, 36.5)  # on the normal fault's trace
    tree = dh.displacement_hazard(spec, data, site, model="logic_tree", displacements=[0.1, 1.0, 3.0])
    assert tree.style == "normal"
    assert set(tree.branches) == set(fdh.applicable_models("normal"))
    assert "youngs_2003" in tree.branches and "chiou_2025" not in tree.branches
    branches = []
    for name, (weight, curve) in tree.branches.items():
        alone = dh.displacement_hazard(spec, data, site, model=name, displacements=[0.1, 1.0, 3.0])
        np.testing.assert_array_equal(curve, alone.rate)  # each branch is the model run alone
        assert weight == pytest.approx(1 / len(tree.branches))
        branches.append(curve)
    np.testing.assert_allclose(tree.rate, np.mean(branches, axis=0), rtol=1e-15)
    assert np.all(tree.quantiles[5.0] <= tree.quantiles[95.0])
    assert np.all(tree.quantiles[5.0] <= tree.rate * (1 + 1e-12)) and np.all(tree.rate <= tree.quantiles[95.0] * (1 + 1e-12))
    dataset = tree.to_dataset()
    assert list(dataset["branch"].values) == list(tree.branches)
    assert dataset.attrs["style_of_faulting"] == "normal"


def test_the_cli_takes_the_models_and_refuses_without_fdhpy(tmp_path, cli, monkeypatch):
    import json

    scene = _map(tmp_path)
    done = cli("map", scene, "-o", tmp_path / "a.nc", "--displacement-hazard", "-118.6 34.3",
               "--displacement-model", "moss_2024", "--displacements", "1 m, 3 m", "--json")
    assert done.code == 0, done.err
    shown = json.loads(done.out)["displacement_hazard"]
    assert shown["model"] == "moss_2024" and shown["style"] == "reverse"
    assert shown["annual_exceedance_rate"]["value"][0] > shown["annual_exceedance_rate"]["value"][1] > 0
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "fdhpy" else real(name, *a))
    refused = cli("map", scene, "-o", tmp_path / "b.nc", "--displacement-hazard", "-118.6 34.3",
                  "--displacement-model", "moss_2024")
    assert_clean_error(refused, "pip install 'faultslip[fdh]'")
    assert not (tmp_path / "b.nc").exists()
