"""Maps, sources, rupture sets and hazard engines (docs/hazard.md, docs/studies.md)."""

from __future__ import annotations

import numpy as np

from ._common import _load, _load_with, _machine


def _map_dataset(segments: list):
    """A map's segment rows (benchmarks/san_andreas_map.py) as the Dataset faultslip.studies.maps reads, so its own
    table is rendered, not a copy of it."""
    import numpy as np
    import xarray as xr

    names = [key for key in segments[0] if key not in ("segment", "observed_slip_event")]
    return xr.Dataset({name: ("segment", np.array([np.nan if row[name] is None else row[name] for row in segments]))
                       for name in names if name != "model_error" or any(row[name] is not None for row in segments)},
                      coords={"segment": [row["segment"] for row in segments]})


def _against_observed(segments: list) -> str:
    """What the table shows, in a sentence: the slip ratios of the observed events, and the recurrence ratios."""
    slips = [f"{row['slip_ratio']:.2f} on {row['segment']}" + (f" ({row['observed_slip_event']})"
                                                               if row["observed_slip_event"] else "")
             for row in segments if row["slip_ratio"] is not None]
    ratios = [(row["recurrence_ratio"], row["segment"]) for row in segments if row["recurrence_ratio"] is not None]
    if not ratios:
        return f"Predicted over observed slip per event: {', '.join(slips)}."
    low, high = min(ratios), max(ratios)
    said = ("over-predicted on every segment where it is observed" if low[0] > 1 else
            "under-predicted on every segment where it is observed" if high[0] < 1 else "predicted over observed")
    return (f"Predicted over observed slip per event: {', '.join(slips)}. Recurrence is {said}: {low[0]:.2f} "
            f"({low[1]}) to {high[0]:.2f} ({high[1]}) times.")


def san_andreas_map_table() -> str | None:
    result = _load("san_andreas_map.json")
    if result is None:
        return None
    from faultslip.studies.maps import observed_table

    parts = []
    for name, heading in (("seed_law", "The seed law"), ("rate_state", "One rate-and-state block a segment")):
        segments = result[name]["segments"]
        parts.append(f"**{heading}** (`{result[name]['config']}`):\n\n{observed_table(_map_dataset(segments))}\n\n"
                     + _against_observed(segments))
    return "\n\n".join(parts) + f"\n\n`python benchmarks/san_andreas_map.py`. {_machine(result)}"


def california_scaling_table() -> str | None:
    result = _load_with("docs_numbers.json", "california_sources")
    if result is None:
        return None
    sources = result["california_sources"]
    relations = list(sources[0]["empirical"])
    rows = ["| segment | moment rate (N m/yr) | faultslip Mw | " + " | ".join(
        relation.replace(", strike-slip", "") for relation in relations) + " |", "| --- " * (3 + len(relations)) + "|"]
    excess = []
    for source in sources:
        cells = []
        for relation in relations:
            entry = source["empirical"][relation]
            if entry.get("sigma") is not None:
                cells.append(f"{entry['magnitude']:.2f} ± {entry['sigma']:.2f}")
            else:
                cells.append(f"{entry['magnitude']:.2f} ({entry['range'][0]:.2f}-{entry['range'][1]:.2f})")
            excess.append(source["magnitude"] - entry["magnitude"])
        rows.append(f"| {source['id']} | {source['moment_rate']:.3g} | {source['magnitude']:.2f} | " + " | ".join(cells)
                    + " |")
    return ("\n".join(rows) + f"\n\nfaultslip's Mw less the relations': {min(excess):+.2f} to {max(excess):+.2f}. "
            f"`python benchmarks/docs_numbers.py`. {_machine(result)}")


def rupture_sets_table() -> str | None:
    result = _load_with("docs_numbers.json", "rupture_sets")
    if result is None:
        return None
    rows = ["| branch | sections | ruptures allowed | with a rate | multi-fault with a rate | slip rates released to | "
            "b of the solved MFD | shape misfit |", "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for branch in result["rupture_sets"]:
        rows.append(f"| {branch['relation']} | {branch['sections']} | {branch['ruptures']} | {branch['ruptures_with_rate']} "
                    f"| {branch['multi_fault_ruptures_with_rate']} | {branch['budget_error']:.1e} | "
                    f"{branch['b_value']:.3f} | {branch['shape_misfit']:.2g} |")
    return "\n".join(rows) + f"\n\n`python benchmarks/docs_numbers.py`. {_machine(result)}"


def rupture_rate_stability_table() -> str | None:
    result = _load("rupture_rate_stability.json")
    if result is None:
        return None
    rows = ["| rates | draw | rule sets solved | moved by more than 1e-6 of the largest rate | by more than 1e-3 | "
            "largest move | refused after the change |", "| --- | --- | --- | --- | --- | --- | --- |"]
    names = {"least_norm": "least-norm (faultslip)", "nnls": "NNLS's own answer (the baseline)"}
    cases, sizes = {}, []
    for key, name in names.items():
        for seed, draw in result["draws"].items():
            moves = [row[key]["moved"] for row in draw if row[key]["moved"] is not None]
            finite = [move for move in moves if np.isfinite(move)]
            rows.append(f"| {name} | seed {seed} | {sum(not row[key]['refused'] for row in draw)} of {len(draw)} | "
                        f"{sum(move > 1e-6 for move in moves)} | {sum(move > 1e-3 for move in moves)} | "
                        f"{max(finite, default=0.0):.1e} | {sum(not np.isfinite(move) for move in moves)} |")
    for draw in result["draws"].values():
        for row in draw:
            sizes.append(row["ruptures"])
            case = row["least_norm"]["case"]
            if case is not None:
                cases[case] = cases.get(case, 0) + 1
    return ("\n".join(rows) + f"\n\nRule sets drawn at random over `configs/{result['system']}` ({min(sizes)} to "
            f"{max(sizes)} ruptures), each solved again with every slip moved by a relative {result['change']:g} "
            f"(seeds {', '.join(map(str, result['change_seeds']))}); seed 7's draw found the cases the least-norm "
            "step handles, seed 8's was drawn after. The baseline does the same work with NNLS's own answer in place "
            "of the least-norm step. The cases the least-norm step met: "
            + "; ".join(f"{case}, {count}" for case, count in sorted(cases.items()))
            + f". `python benchmarks/rupture_rate_stability.py`. {_machine(result)}")


def rupture_rate_exact_point_table() -> str | None:
    result = _load("rupture_rate_exact_point.json")
    if result is None:
        return None
    rows = ["| rule set | ruptures | rows met: ridge / exact | norm: ridge / exact | exact from ridge | moved by "
            f"{result['change']:g}: ridge / exact | faultslip's rates moved |", "| --- | --- | --- | --- | --- | --- | --- |"]
    for row in result["rule_sets"]:
        moved = ("not nearly one point after the change" if row["ridge_moved"] is None
                 else f"{row['ridge_moved']:.1e} / {row['exact_moved']:.1e}")
        rows.append(f"| seed {row['seed']}, {row['index']} ({row['relation']}) | {row['ruptures']} | "
                    f"{row['ridge_meets_rows']:.0e} / {row['exact_meets_rows']:.0e} | {row['ridge_norm']:.3g} / "
                    f"{row['exact_norm']:.3g} | {row['exact_from_ridge']:.2g} | {moved} | {row['rates_moved']:.1e} |")
    return ("\n".join(rows) + f"\n\nThe first {result['count']} rule sets of each draw above (at most "
            f"{result['most_ruptures']} ruptures) whose least-norm step met the nearly-one-point case. The exact "
            "least-norm point, as an interior-point solver finds it (scipy's trust-constr, gtol and xtol 1e-14, from "
            "the ridge's rates), meets the rows to round-off, but lies far from the ridge's rates, its norm is "
            "larger, and the change in the slips moves it far more than the ridge's: where the rates that fit are "
            "nearly one point, that point is ill-determined. Distances and moves are over the largest rate, each in the "
            f"scaled rates the step solves for; the moves are the largest over seeds "
            f"{', '.join(map(str, result['change_seeds']))}. `python benchmarks/rupture_rate_exact_point.py`. "
            f"{_machine(result)}")


def rupture_rate_cost_table() -> str | None:
    result = _load("rupture_rate_cost.json")
    if result is None:
        return None
    rows = ["| system | sections | ruptures | enumeration and magnitudes, CPU | rate solve, CPU | estimated / CPU |",
            "| --- | --- | --- | --- | --- | --- |"]
    for row in result["cuts"]:
        rows.append(f"| {row['subsection_length'] / 1e3:g} km sections, {row['relation']}"
                    f"{' (held out)' if row['held_out'] else ''} | {row['sections']} | {row['ruptures']:,} | "
                    f"{row['enumeration_seconds']:.2g} s | {row['solve_seconds']:.3g} s | "
                    f"{row['estimate_over_cpu']:.2f} |")
    drawn = result["drawn"]
    ratios = [row["estimate_over_cpu"] for row in drawn]
    longest = max(row["solve_seconds"] + row["enumeration_seconds"] for row in drawn)
    fit = result["fit"]
    return ("\n".join(rows) + f"\n\n`configs/{result['system']}` cut into sections (jump 5 km, turn 60 degrees), "
            "its rates solved as a map solves them, in process CPU. The model: seconds = branches x (overhead + c x "
            f"(sections + 41)^2 x ruptures + e x ruptures), with c = {fit['rate_seconds']:.3g} s, overhead "
            f"{fit['overhead_seconds']:.2g} s (the 95th percentile of {len(drawn)} rule sets drawn at random, seed "
            f"{result['draw_seed']}) and e = {fit['enumeration_seconds']:.2g} s, fitted on the cuts not held out "
            f"and carried to the machine state of the families' cost group. The drawn rule sets took at most "
            f"{longest:.2g} s, and were estimated at {min(ratios):.2f} to {max(ratios):.1f} times it: the overhead "
            f"bounds them. `python benchmarks/rupture_rate_cost.py`. {_machine(result)}")


def hazard_chain_table() -> str | None:
    result = _load("hazard_chain.json")
    if result is None:
        return None
    kinds = list(result["kinds"])
    rows = ["| site | " + " | ".join(kind.replace("_", " ") for kind in kinds) + " |", "| --- " * (1 + len(kinds)) + "|"]
    for site, (lon, lat) in result["sites"].items():
        rows.append(f"| {site} ({lon:g}, {lat:g}) | " + " | ".join(
            f"{result['kinds'][kind]['pga_10pct_50yr_g'][site]:.2f} g" for kind in kinds) + " |")
    above_five = {}
    for kind in kinds:  # the budget's M >= 5 events a year on the segment drawn, by branch
        for relation, mfd in result["kinds"][kind]["mfd"].items():
            magnitudes = mfd["min_magnitude"] + mfd["bin_width"] * np.arange(len(mfd["rates"]["value"]))
            rates = np.asarray(mfd["rates"]["value"])
            above_five.setdefault(kind, []).append(float(rates[magnitudes >= 5.0 - 1e-9].sum()))
    said = "; ".join(f"{kind.replace('_', ' ')} {min(v):.2g}-{max(v):.2g}" for kind, v in above_five.items())
    return ("\n".join(rows) + f"\n\nM ≥ 5 events a year on the segment drawn, over the three branches: {said}. "
            f"`python benchmarks/hazard_chain.py` (needs the engine: `pip install '.[hazard]'`). {_machine(result)}")


#: Leonard's (2010) Table 6 as printed: Mw - log10 A and Mw - (5/3) log10 L, by setting.
LEONARD_PRINTED = {"strike-slip": (3.99, 4.17), "dip-slip": (4.00, 4.24), "stable-continental": (4.19, 4.32)}


def leonard_table_6_table() -> str | None:
    result = _load_with("docs_numbers.json", "leonard_table_6")
    if result is None:
        return None
    computed = result["leonard_table_6"]
    settings = list(LEONARD_PRINTED)
    rows = ["| | printed | computed |", "| --- | --- | --- |"]
    for index, label in ((0, "Mw(A) intercepts (strike-slip, dip-slip, stable continental)"),
                         (1, "Mw(L) intercepts, slope 5/3")):
        key = ("area", "length")[index]
        rows.append(f"| {label} | " + ", ".join(f"{LEONARD_PRINTED[s][index]:.2f}" for s in settings) + " | "
                    + ", ".join(f"{computed[s][key]:.3f}" for s in settings) + " |")
    return "\n".join(rows) + f"\n\n`python benchmarks/docs_numbers.py`. {_machine(result)}"


def engine_branches_table() -> str | None:
    result = _load("engine_branches.json")
    if result is None:
        return None
    branches = result["branches"]
    levels = next(iter(branches.values()))["levels_g"]
    shown = [k for k, level in enumerate(levels) if level in (0.01, 0.05, 0.1, 0.2, 0.5, 1.0)]
    rows = ["| source model | T (yr) | " + " | ".join(f"PGA > {levels[k]:g} g" for k in shown) + " |",
            "| --- | --- | " + " | ".join("---" for _ in shown) + " |"]
    for name, branch in branches.items():
        rows.append(f"| {name} | {branch['investigation_time_yr']:g} | "
                    + " | ".join(f"{branch['annual_rate'][k]:.3g}" for k in shown) + " |")
    return ("\n".join(rows) + f"\n\nEquivalent annual rates, -ln(1 - PoE) / T, at {result['site']} "
            "(benchmarks/engine_branches.py, the engine's classical calculator on each job faultslip writes). "
            + _machine(result))


def _share(value: float) -> str:
    """A share as a percentage, a round-off's sign dropped (SHERIFS's logs release -3e-6 of a slip rate)."""
    return f"{0.0 if abs(value) < 5e-4 else value:.1%}"


def sherifs_example_table() -> str | None:
    result = _load("sherifs_example.json")
    if result is None:
        return None
    rows = ["| rupture set | quantity | SHERIFS (logged sample) | faultslip |", "| --- | --- | --- | --- |"]
    for name, sides in result["sets"].items():
        ours = sides["faultslip"]
        for label, theirs in sides["sherifs"].items():
            sample = label.split(" sample ")[1]
            rows.append(f"| {name} | moment rate of the faults, mu A s | {theirs['moment_rate_initial']:.3g} N m/yr "
                        f"(sample {sample}) | {ours['moment_rate_initial']:.3g} N m/yr |")
            rows.append(f"| {name} | released by the ruptures; left unassigned | {theirs['moment_rate_released']:.3g}; "
                        f"{theirs['unassigned_share']:.1%} | {ours['moment_rate_released']:.3g}; "
                        f"{abs(ours['unassigned_share']):.1e} |")
            rows.append(f"| {name} | rate of M >= 6 | {theirs['rate_m6']:.3g} /yr | {ours['rate_m6']:.3g} /yr |")
            rows.append(f"| {name} | b of the target; of the solved distribution (least squares over its bins) | "
                        f"{theirs['b_target']:.3f} (sampled); {theirs['b_solved']:.3f} | {ours['b_target']:.3f}; "
                        f"{ours['b_value']:.3f} |")
            rows.append(f"| {name} | smallest magnitude | {theirs['smallest_magnitude']:.1f} (its M_min) | "
                        f"{ours['smallest_magnitude']:.2f} (one 3 km section) |")
            for fault in sorted(ours["participation"]):
                mine, theirs_p = ours["participation"][fault], theirs["participation"][fault]
                rows.append(f"| {name} | {fault}: participation at M >= 5, 5.5, 6 (/yr); slip-rate misfit | "
                            + ", ".join(f"{theirs_p[t]:.2g}" for t in ("5", "5.5", "6"))
                            + f"; {_share(theirs['slip_rate_misfit'][fault])} | "
                            + ", ".join(f"{mine[t]:.2g}" for t in ("5", "5.5", "6"))
                            + f"; {abs(ours['slip_rate_misfit'][fault]):.0e} |")
            largest = ", ".join(f"{key} {theirs['mmax'][key]:.1f} / {ours['mmax'][key]:.2f}"
                                for key in theirs["mmax"] if key in ours["mmax"])
            rows.append(f"| {name} | largest magnitude of each source, SHERIFS / faultslip | {largest} | |")
    first = next(iter(result["sets"].values()))["faultslip"]
    apart = "; ".join(f"{name} {theirs['moment_rate_initial'] / sides['faultslip']['moment_rate_initial'] - 1:+.1%}"
                      for name, sides in result["sets"].items() for theirs in sides["sherifs"].values())
    return ("\n".join(rows) + f"\n\nThe faults' moment rate, SHERIFS's over faultslip's - 1: {apart}. "
            f"faultslip: {first['sections']} sections of about 3 km, solved on the Wells & "
            "Coppersmith (1994) area branch with b = 1; SHERIFS: the logged samples whose files agree with one another "
            "(benchmarks/data/sherifs_example_logs.txt names each file and commit). " + _machine(result))


def truncated_gr_moment_rate_table() -> str | None:
    """docs/hazard.md: the binned moment rate faultslip balances against the engine's continuous integral."""
    result = _load_with("docs_numbers.json", "truncated_gr_moment_rates")
    if result is None:
        return None
    found = result["truncated_gr_moment_rates"]
    by_b = ", ".join(f"{100 * row['apart']:.2f} % at b = {row['b_value']:g}" for row in found["by_b_value"])
    by_width = ", ".join(f"{100 * row['apart']:.2f} % at {row['bin_width']:g}" for row in found["by_bin_width"])
    return (f"The binned sum exceeds the integral by {by_b} (bins of {found['bin_width']:g}), and by {by_width} "
            f"(b = {found['b_value']:g}), whatever the bounds: per bin the two differ by [sinh(x) / x] [y / sinh(y)] "
            "(`faultslip.fault.mfd.continuous_moment_rate`). A logic tree that moves the engine's maximum magnitude "
            f"at constant moment rate starts from the integral. `python benchmarks/docs_numbers.py`. {_machine(result)}")


#: The tables this module renders, by the marker name in the pages.
TABLES = {
    "san_andreas_map": san_andreas_map_table,
    "california_scaling": california_scaling_table,
    "rupture_sets": rupture_sets_table,
    "rupture_rate_stability": rupture_rate_stability_table,
    "rupture_rate_cost": rupture_rate_cost_table,
    "rupture_rate_exact_point": rupture_rate_exact_point_table,
    "hazard_chain": hazard_chain_table,
    "leonard_table_6": leonard_table_6_table,
    "engine_branches": engine_branches_table,
    "sherifs_example": sherifs_example_table,
    "truncated_gr_moment_rate": truncated_gr_moment_rate_table,
}
