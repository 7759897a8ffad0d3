"""SHERIFS's Example beside faultslip's rupture set of the same faults and rupture sets (issue 73).

    python benchmarks/sherifs_example.py     # a few seconds; writes benchmarks/results/sherifs_example.json

faultslip reads SHERIFS's own input files (configs/sherifs_example/: Faults_geometry.txt, Faults_properties.txt,
ruptures.txt) through configs/sherifs_example.toml (Set_1) and configs/sherifs_example_set2.toml (Set_2), and
solves its rupture set on the Wells & Coppersmith (1994) area branch, as SHERIFS's logged run
(Example_Model/bg_BG_1/WC1994_A_m, b from 0.95 to 1.05) does. SHERIFS's side is its log files
(benchmarks/data/sherifs_example_logs.txt, each with its path and commit), checked for agreement with one another
before use. Side by side, per rupture set:

* the faults' moment rate mu A s, and the share of it the ruptures release (SHERIFS leaves the rest unassigned,
  its "NMS" share);
* the rate of ruptures of M >= 6 (each in its 0.1 bin: M >= 5.95);
* each fault's participation: the rate of ruptures it takes part in, at or above M 5, 5.5 and 6;
* each fault's slip-rate misfit: 1 - the slip rate its ruptures release over its slip rate;
* each rupture's largest magnitude.

Both count a magnitude's moment as 10^(1.5 M + 9.1) (SHERIFS's logs say so; faultslip's Mw, fault.mfd).
"""

from __future__ import annotations

import ast
import json
import math
import re
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from faultslip import __version__  # noqa: E402
from faultslip.studies.maps import read_map, run_map  # noqa: E402
from faultslip.studies.rupture_sets import rupture_set  # noqa: E402
from faultslip.units import JULIAN_YEAR  # noqa: E402
from provenance import stamp  # noqa: E402

LOGS = ROOT / "benchmarks" / "data" / "sherifs_example_logs.txt"
OUT = ROOT / "benchmarks" / "results" / "sherifs_example.json"
CONFIGS = {"Set_1": ROOT / "configs" / "sherifs_example.toml", "Set_2": ROOT / "configs" / "sherifs_example_set2.toml"}
SHEAR_MODULUS = 30e9  # Pa: Faults_properties.txt's, which SHERIFS's mu A s takes
#: the magnitudes the participation is counted at or above (each in its 0.1 bin)
THRESHOLDS = (5.0, 5.5, 6.0)
BIN_EDGE = 0.05


def sherifs_moment(magnitude):
    """A bin's moment as SHERIFS's logs count it (N m)."""
    return 10.0 ** (1.5 * np.asarray(magnitude, float) + 9.1)


def read_logs(path: Path = LOGS) -> dict:
    """The log excerpts: (set, sample) -> {kind: (text, path, commit)}."""
    blocks = {}
    current = None
    for line in path.read_text(encoding="utf-8").splitlines():
        match = re.match(r"== (\S+) sample (\d+) (\S+) (\S+) @ ([0-9a-f]{40})$", line)
        if match:
            name, sample, kind, where, commit = match.groups()
            current = blocks.setdefault((name, int(sample)), {})
            current[kind] = ([], where, commit)
        elif current is not None and line and not line.startswith("#"):
            current[kind][0].append(line)
    return {key: {kind: ("\n".join(lines), where, commit) for kind, (lines, where, commit) in value.items()}
            for key, value in blocks.items()}


def _faults_of(name: str) -> tuple:
    """SHERIFS's source name -> its faults: 'Example_Model_F1' -> (F1,), a scenario -> its faults in order."""
    if "scenario" in name:
        return tuple(re.findall(r"\['([^']+)'\]", name))
    return (name.rsplit("_", 1)[-1],)


def sherifs_side(logs: dict) -> dict:
    """Each logged sample's quantities, with its files' agreement checked."""
    out = {}
    for (name, sample), files in sorted(logs.items()):
        sources = []
        for line in files["mdf"][0].splitlines():
            label, first, rates = line.split("\t")
            rates = np.array(rates.split(), float)
            sources.append((_faults_of(label), float(first) + 0.1 * np.arange(rates.size), rates))
        calculation = dict(re.findall(r"^(Moment_rate_\w+|Ratio of NMS)[^\t]*\t\s*([0-9.e+]+)", files["calculation"][0],
                                      re.M))
        slip_rate = {row.split("\t")[0]: float(row.split("\t")[1]) for row in files["slip_rate"][0].splitlines()}
        mmax_text = (files.get("Mmax") or logs.get((name, 4), {}).get("Mmax") or logs[(name, 5)]["Mmax"])[0]
        areas, mmax = {}, {}
        for row in mmax_text.splitlines():
            key, _length, _ratio, _width, area, largest = row.split("\t")
            faults = tuple(v[0] for v in ast.literal_eval(key).values()) if key.startswith("{") else (key,)
            areas[faults], mmax[faults] = float(area) * 1e6, float(largest)
        general = dict(row.split("\t") for row in files["general"][0].splitlines())
        system_bins = np.round(np.concatenate([m for _, m, _ in sources]), 6)
        system = {m: 0.0 for m in np.unique(system_bins)}
        for _, m, rates in sources:
            for magnitude, rate in zip(np.round(m, 6), rates):
                system[magnitude] += rate
        bins = np.array([m for m, r in system.items() if r > 0])
        solved_b = float(-np.polyfit(bins, np.log10([system[m] for m in bins]), 1)[0])
        final = float(sum(np.sum(rates * sherifs_moment(m)) for _, m, rates in sources))
        initial = SHEAR_MODULUS * sum(areas[(f,)] * slip_rate[f] * 1e-3 for f in slip_rate)
        logged_final, logged_initial = (float(calculation["Moment_rate_faults_final"]),
                                        float(calculation["Moment_rate_fault_initial"]))
        checks = {"final_from_mdf_over_logged": final / logged_final,
                  "initial_from_areas_over_logged": initial / logged_initial}
        faults = sorted(slip_rate)
        participation, misfit = {}, {}
        for fault in faults:
            mine = [(m, r) for f, m, r in sources if fault in f]
            participation[fault] = {f"{t:g}": float(sum(r[m >= t - BIN_EDGE].sum() for m, r in mine))
                                    for t in THRESHOLDS}
            released = sum(float(np.sum(r * sherifs_moment(m))) / (SHEAR_MODULUS * areas[f])
                           for f, m, r in sources if fault in f)  # uniform slip over the source's area (m/yr)
            misfit[fault] = 1.0 - released / (slip_rate[fault] * 1e-3)
        out[f"{name} sample {sample}"] = {
            "set": name, "sample": sample, "files": {kind: {"path": value[1], "commit": value[2]}
                                                     for kind, value in files.items()},
            "checks": checks, "moment_rate_initial": logged_initial, "moment_rate_released": logged_final,
            "unassigned_share": 1.0 - logged_final / logged_initial, "nms_ratio_logged": float(calculation["Ratio of NMS"]),
            "rate_m6": float(sum(r[m >= 6.0 - BIN_EDGE].sum() for _, m, r in sources)),
            "b_target": float(general["b_value"]), "b_solved": solved_b, "smallest_magnitude": float(general["M_tronc"]),
            "participation": participation, "slip_rate_misfit": misfit,
            "mmax": {"+".join(k): v for k, v in mmax.items()}, "slip_rate_sampled": slip_rate}
    return out


def faultslip_side(name: str) -> dict:
    """faultslip's rupture set of the same faults and set, on the W&C 1994 area branch."""
    spec = read_map(CONFIGS[name])
    dataset = run_map(spec)
    result = rupture_set(spec, dataset, spec.rupture_rules, relation="WC1994")
    sections = result.sections
    area = sections.area
    year_rate = sections.slip_rate * JULIAN_YEAR  # m/yr
    initial = float(result.shear_modulus * np.sum(area * year_rate))
    released_moment = float(result.shear_modulus * np.sum(area[:, None] * result.slip * result.rate[None, :]))
    faults_of = [tuple(dict.fromkeys(sections.fault_ids[sections.fault[s]] for s in path)) for path in result.ruptures]
    participation, misfit, mmax = {}, {}, {}
    released = result.released
    for index, fault in enumerate(sections.fault_ids):
        mine = np.array([fault in f for f in faults_of])
        participation[fault] = {f"{t:g}": float(result.rate[mine & (result.magnitude >= t - BIN_EDGE)].sum())
                                for t in THRESHOLDS}
        own = sections.fault == index
        misfit[fault] = 1.0 - float(np.sum(released[own] * area[own]) / np.sum(result.budget[own] * area[own]))
    for faults, magnitude in zip(faults_of, result.magnitude):
        key = "+".join(faults)
        mmax[key] = max(mmax.get(key, -math.inf), float(magnitude))
    return {"moment_rate_initial": initial, "moment_rate_released": released_moment,
            "moment_rate_released_sherifs_formula": float(np.sum(result.rate * sherifs_moment(result.magnitude))),
            "unassigned_share": 1.0 - released_moment / initial,
            "rate_m6": float(result.rate[result.magnitude >= 6.0 - BIN_EDGE].sum()),
            "participation": participation, "slip_rate_misfit": misfit, "mmax": mmax,
            "sections": sections.count, "ruptures": len(result.ruptures), "with_rate": int((result.rate > 0).sum()),
            "budget_error": result.budget_error, "b_value": result.b_value_fit()["b"], "b_target": result.rules.b_value,
            "smallest_magnitude": float(result.magnitude.min()),
            "fault_area": {fault: float(area[sections.fault == i].sum()) for i, fault in enumerate(sections.fault_ids)}}


def main() -> int:
    sherifs = sherifs_side(read_logs())
    for label, sample in sherifs.items():
        for check, ratio in sample["checks"].items():
            if abs(ratio - 1.0) > 1e-3:
                raise SystemExit(f"{label}: the logs disagree with one another ({check} = {ratio:.6f})")
    result = {"sets": {}}
    for name in CONFIGS:
        result["sets"][name] = {"faultslip": faultslip_side(name),
                                "sherifs": {label: s for label, s in sherifs.items() if s["set"] == name}}
    OUT.write_text(json.dumps({**stamp(), "faultslip": __version__, **result}, indent=1) + "\n", encoding="utf-8")
    for name, sides in result["sets"].items():
        ours = sides["faultslip"]
        for label, theirs in sides["sherifs"].items():
            print(f"{label}: moment rate {theirs['moment_rate_released']:.3g} released of {theirs['moment_rate_initial']:.3g}"
                  f" (SHERIFS) / {ours['moment_rate_released']:.3g} of {ours['moment_rate_initial']:.3g} (faultslip); "
                  f"M>=6 {theirs['rate_m6']:.3g} / {ours['rate_m6']:.3g} per yr")
    return 0


if __name__ == "__main__":
    sys.exit(main())
