"""Write the README's measured tables from benchmarks/results/*.json (called by run.py; or run alone).

    python benchmarks/readme.py

Each table is replaced between ``<!-- table:NAME -->`` and ``<!-- /table:NAME -->`` and states the
machine and date of the run that produced it. Nothing here is typed by hand.
"""

from __future__ import annotations

import json
import math
import re
import statistics
from pathlib import Path

import numpy as np

from provenance import listed  # one stamp for every results file

ROOT = Path(__file__).resolve().parent.parent
RESULTS = ROOT / "benchmarks" / "results"


def _load(name):
    path = RESULTS / name
    return json.loads(path.read_text(encoding="utf-8")) if path.exists() else None


def _packages(result) -> str:
    """The packages a result was measured with (provenance.stamp), as a sentence; empty for an older result."""
    versions = listed(result)
    return f" Packages: {versions}." if versions else ""


def _machine(result) -> str:
    machine = result.get("machine", "")
    if isinstance(machine, dict):
        machine = f"{machine.get('platform', '')}, Python {machine.get('python', '')}"
    return f"Measured on {machine}, {result.get('date', 'date not recorded')}.{_packages(result)}"


def benchmarks_table() -> str | None:
    latest = _load("latest.json")
    if latest is None:
        return None
    rows = ["| benchmark | result |", "| --- | --- |"]
    one = latest["exact_vs_integrators"]["one_cycle"]
    for target, row in one["per_accuracy"].items():
        rows.append(f"| one limit cycle at {target} (period, stress drop, swing): exact cycle vs {row['baseline']} "
                    f"| {row['exact_s'] * 1e3:.3f} ms vs {row['baseline_s'] * 1e3:.3f} ms: **{row['ratio']:.1f}×** |")
    seq = latest["exact_vs_integrators"]["distinct_cycles"]
    rows.append(f"| 100 distinct cycles (Cameron's law from rest, 1e-6): simulate vs {seq['baseline']} "
                f"| {seq['faultslip_s'] * 1e3:.1f} ms vs {seq['baseline_s'] * 1e3:.1f} ms: **{seq['ratio']:.1f}×** |")
    fault = latest["fault_scale"]
    rows.append(f"| 100 cycles of the 1906 scene (analytic slip phases) | **{fault['ours_s'] * 1e3:.1f} ms** "
                f"(DOP853 slip phases at rtol 1e-6: {fault['event_driven_DOP853_s'] * 1e3:.0f} ms) |")
    for solver, row in fault["generic_regularized_w0.01V"].items():
        # a failure is reported as what it is, never as a time
        result = (f"fails: {row['outcome'][8:100]}" if row["seconds"] is None or row["outcome"].startswith("failed")
                  else f"{row['seconds']:.1f} s: {row['outcome'][:90]}")
        rows.append(f"| same task, generic regularised friction ({solver}, w = 0.01 V, rtol 1e-6) | {result} |")
    auto = latest["auto_vs_fixed"]
    rows.append(f"| auto against the best fixed method, total over the standard scenes | "
                f"{auto['total_auto_s'] * 1e3:.1f} ms vs {auto['total_best_fixed_s'] * 1e3:.1f} ms: "
                f"**{auto['ratio_total']:.2f}×** |")
    fit = latest.get("fit_bootstrap")
    if fit:
        rows.append(f"| fit: {fit['resamples']} bootstrap resamples of {fit['points']} points, batched Levenberg-Marquardt "
                    f"with the analytic Jacobian vs one least_squares per resample with the same analytic Jacobian | "
                    f"{fit['batched_s']:.2f} s vs "
                    f"{fit['one_at_a_time_s']:.2f} s: **{fit['ratio']:.1f}×**; intervals agree to "
                    f"{fit['interval_difference']:.0e} |")
    step = latest.get("rate_state_step")
    if step:
        rows.append(f"| rate-and-state velocity step (aging law, 4001 samples) at ≤ 1e-8 in friction: faultslip "
                    f"(auto: {step.get('method', 'lsoda')}, log states) vs {step['baseline']} (target ≥ 3×) | "
                    f"{step['ours_s'] * 1e3:.2f} ms vs {step['baseline_s'] * 1e3:.2f} ms: **{step['ratio']:.1f}×** |")
        peer = step.get("rsfmodel")
        if peer and peer.get("available"):
            rows.append(f"| the same step against rsfmodel's own code (jrleeman/rsfmodel, odeint through its model "
                        f"class), at its loosest rtol meeting 1e-8 ({peer['rtol']:g}) and at its default 1e-12 | "
                        f"{peer['seconds'] * 1e3:.1f} ms and {peer['default_seconds'] * 1e3:.1f} ms against our "
                        f"{peer['ours_s'] * 1e3:.2f} ms: **{peer['ratio']:.0f}×** and **{peer['default_ratio']:.0f}×** |")
        elif peer:
            rows.append(f"| the same step against rsfmodel's own code | not run on this machine: {peer['reason']} |")
        if "lsoda_s" in step:
            rows.append(f"| the same step without numba (auto takes LSODA with the analytic Jacobian); the compiled "
                        f"kernel's first call in a process, compile or cache load, is {step['first_call_s']:.1f} s, "
                        f"paid once | {step['lsoda_s'] * 1e3:.2f} ms: **{step['lsoda_ratio']:.1f}×** |")
    cycles = latest.get("rate_state_cycles")
    if cycles:
        rows.append(f"| 100 quasi-dynamic rate-and-state cycles at fault scale (SEAS BP1 friction, K / K_c = "
                    f"{cycles['stiffness_ratio']:.2f}; target < 1 s) | **{cycles['seconds']:.2f} s** "
                    f"({cycles['steps']} {cycles.get('method', 'dopri5')} steps; recurrence "
                    f"{cycles['recurrence_years']:.0f} yr) |")
    sweep = _load("sweep.json")
    for row in (sweep or {}).get("engine", []):
        rows.append(f"| study engine against a numpy kernel computing the same 17 outputs, {row['cells']:.0e} cells in "
                    f"memory (target ≥ {row['target']}) | {row['engine_s'] * 1e3:.0f} ms vs {row['numpy_s'] * 1e3:.0f} ms: "
                    f"**{row['fraction_of_numpy']:.2f}** of numpy's throughput |")
    writer = (sweep or {}).get("writer")
    if writer:
        rows.append(f"| default `faultslip sweep` of {writer['cells']:.0e} cells, 17 outputs, against a single-threaded "
                    f"numpy + netCDF4 writer (zlib 1, shuffle, same chunks), both whole commands (target ≤ "
                    f"{writer['target']}) | {writer['ours_s']:.1f} s vs {writer['baseline_s']:.1f} s: "
                    f"**{writer['ratio']:.2f}×**; peak memory {writer['ours_peak_memory_bytes'] / 2**20:.0f} vs "
                    f"{writer['baseline_peak_memory_bytes'] / 2**20:.0f} MiB |")
    bottom = (sweep or {}).get("floor")
    if bottom:
        parts = bottom["parts_s"]
        seconds = bottom["sweep_s"]
        rows.append(f"| default `faultslip sweep` of {bottom['cells']:.0e} cells against the machine's floor computed in "
                    f"the same run: numpy kernel {parts['kernel']:.2f} s + shuffle {parts['shuffle']:.2f} s + ISA-L "
                    f"level 1 {parts['deflate']:.2f} s of CPU over {bottom['cores']} cores, plus a buffered write of "
                    f"{bottom['compressed_bytes'] / 1e9:.2f} GB ({parts['write']:.2f} s) (target ≤ 2×) | "
                    f"{seconds['default (2 workers)']:.2f} s vs {bottom['floor_s']:.2f} s: "
                    f"**{bottom['ratio_to_floor']:.2f}×** the floor; of it, the whole command's fixed cost (Python, "
                    f"imports, layout, the file) is the one-cell sweep's {seconds['one cell']:.2f} s |")
        rows.append(f"| the second core: the default sweep (2 workers) against `--workers 1`, whole commands, median of "
                    f"{bottom['repeats']} interleaved (target ≥ 1.6×) | {seconds['default (2 workers)']:.2f} s vs "
                    f"{seconds['--workers 1']:.2f} s: **{bottom['second_worker_speedup']:.2f}×**; without the fixed "
                    f"{seconds['one cell']:.2f} s, "
                    f"{(seconds['--workers 1'] - seconds['one cell']) / (seconds['default (2 workers)'] - seconds['one cell']):.2f}× |")
        state = bottom.get("state")
        if state:
            pairs = ", ".join(f"{one / two:.2f}" for two, one in state["seconds_per_window"]["each pair"])
            rows.append(f"| the machine's state when these two rows were measured | {state['measured_at']}, load "
                        f"average {state['load_average_before']:.2f} before and {state['load_average_after']:.2f} "
                        f"after; the second worker's gain in each pair: {pairs}. The gain depends on the machine: "
                        "where shuffling and deflating run faster, the fixed cost weighs more (docs/studies.md)"
                        + (f"; packages: {listed(bottom['stamp'])}" if bottom.get("stamp") else "") + " |")
    pool = {row["cells"]: row["peak_memory_bytes"] for row in (sweep or {}).get("work_against_size", [])
            if row["path"] == "process pool"}
    if 1e7 in pool and 1e8 in pool:
        rows.append(f"| peak memory of the default sweep (whole process tree), 1e7 against 1e8 cells (target: within 5 %) "
                    f"| {pool[1e7] / 2**20:.0f} vs {pool[1e8] / 2**20:.0f} MiB: **{pool[1e8] / pool[1e7] - 1:+.1%}** |")
    return "\n".join(rows) + "\n\n" + _machine(latest)


def sweep_table() -> str | None:
    sweep = _load("sweep.json")
    if not sweep or not sweep.get("work_against_size"):
        return None
    rows = ["| cells | execution path | wall time (whole command) | peak memory (whole process tree) | on disk |",
            "| --- | --- | --- | --- | --- |"]
    for row in sweep["work_against_size"]:
        rows.append(f"| {row['cells']:.0e} | {row['path']} | {row['seconds']:.1f} s | "
                    f"**{row['peak_memory_bytes'] / 2**20:.0f} MiB** | {row['bytes_on_disk'] / 2**30:.2f} GiB |")
    return "\n".join(rows) + "\n\n" + _machine(sweep)


def reliability_table() -> str | None:
    fuzz, kills = _load("fuzz.json"), _load("kills.json")
    if fuzz is None:
        return None
    outcomes = fuzz["outcomes"]
    rows = ["| check | result |", "| --- | --- |",
            f"| mutated inputs run through the CLI (`benchmarks/fuzz.py`) | {fuzz['cases']:,} |",
            f"| answered (exit 0) | {outcomes.get('ok', 0):,} (+ {outcomes.get('mismatch', 0)} tampered files "
            f"that `reproduce` reported as differing) |",
            f"| refused with one sentence, exit 2 | {outcomes.get('clean', 0):,} |",
            f"| tracebacks and multi-line errors | **{sum(outcomes.get(k, 0) for k in ('traceback', 'unclean', 'environment'))}** |",
            f"| silent: a changed input answered as if unchanged (exit 0) | **{outcomes.get('silent', 0)}** |",
            f"| cases over the fuzzer's {fuzz.get('timeout_s', 60):g} s limit | {outcomes.get('timeout', 0)} |"]
    hard = {"zarr": "Zarr stores as written, or damaged (missing, corrupted or swapped chunks, an attribute edited in the "
                    "store or its consolidated metadata), converted",
            "netcdf": "a sweep's sealed netCDF output, bytes mutated, one bit flipped, or an attribute or coordinate "
                      "edited, then reproduced, read as a record or fitted",
            "ledger": "a sweep's failure ledger edited (cells dropped, indices changed) or mutated, then --retry-failed",
            "partial": "an interrupted sweep's partial output (netCDF or Zarr: bytes, an attribute, a coordinate, a "
                       "chunk) or progress record damaged, then --resume (exit 0 must give the run without a stop)",
            "registry": "the fit registry edited (a fit's parameter, its checksum, the version) or mutated, then the "
                        "fit used",
            "catalog": "catalogs: CSV mutated, or faultslip's QuakeML with a value's digit changed, its checksum "
                       "removed or its bytes mutated, then fitted",
            "mseed": "faultslip's miniSEED records with a bit flipped in a data record or bytes mutated, then analysed",
            "table": "a table faultslip ships and reads back (a calibration, a cost model, a declared error) edited "
                     "or mutated, then read by a command",
            "deep": "TOML nested 33 to 3,000 deep", "device": "devices, FIFOs and folders given as files",
            "lock": "symlinks, hard links and FIFOs planted at an output's lock",
            "full": "writes into a full disk (300 kB tmpfs)", "race": "a second writer of another kind holding the output",
            "gaf": "GAF GeoJSON: slip types, MultiLineStrings, repeated ids",
            "fault_2d": "mutated 2-D fault scenes (run, and simulate into a folder)",
            "checkpoint": "a stopped 2-D run's checkpoint flipped, cut, emptied, re-saved, edited or linked, then --resume",
            "stream": "its record streams flipped, cut, grown, deleted or linked to a victim file, then --resume",
            "hazard": "hazard options: b-value, magnitudes, bin width, moment constant, scaling relations",
            "raw": "raw rig records with stiffness, area, trend, steps, windows, priors and posteriors",
            "upload": "classroom uploads with hostile names and headers (no markup may reach the page)",
            "bundle": "fit bundles edited, emptied, shadowed, inflated or given options of the wrong kind, replayed",
            "xlsx": "Excel workbooks: bytes flipped, a stray cell far out, text among the numbers",
            "rfile": "xlook r-files (lines and bytes mutated), reduced",
            "memo": "the unit memo edited or damaged, then units read through it"}
    by_input = fuzz.get("by_input", {})
    for kind, label in hard.items():
        if kind in by_input:
            counts = by_input[kind]
            bad = sum(counts.get(k, 0) for k in ("traceback", "unclean", "environment", "timeout", "silent"))
            differing = f" {counts['mismatch']} reported by `reproduce` as differing," if counts.get("mismatch") else ""
            rows.append(f"| of which {label} | {sum(counts.values()):,}: {counts.get('ok', 0)} answered,{differing} "
                        f"{counts.get('clean', 0)} refused in one sentence, {bad} failures |")
    if kills:
        k, r = kills["kills"], kills["races"]
        rows += [f"| sweeps killed at random moments (`benchmarks/kills.py`) | {k['kill -9']} kill -9 and "
                 f"{k['ctrl-c']} Ctrl-C; {len(k['problems'])} problems (orphan workers, half-written files, "
                 "resumed results that differ) |",
                 f"| two sweeps racing for one output | {r['rounds']} rounds, {r['one_refused']} refused the second "
                 f"writer by name; {len(r['problems'])} problems |"]
    second = _load("fuzz_second_seed.json")
    if second is not None:  # a second seed, the same kinds (issue 69: two new seeds of 10,000 cases)
        o = second["outcomes"]
        rows.append(f"| second seed ({second['seed']}): {second['cases']:,} cases | {o.get('ok', 0):,} answered, "
                    f"{o.get('clean', 0):,} refused in one sentence, **"
                    f"{sum(o.get(k, 0) for k in ('traceback', 'unclean', 'environment', 'timeout', 'silent'))}** "
                    "failures |")
    return "\n".join(rows) + "\n\n" + _machine(fuzz) + (f" Kills: {_machine(kills)[12:]}" if kills else "")


def startup_table() -> str | None:
    startup = _load("startup.json")
    if startup is None:
        return None
    rows = ["| command | median wall time | against `python -c \"import numpy\"` | target |", "| --- | --- | --- | --- |"]
    for name, seconds in startup["seconds"].items():
        target = startup["targets"].get(name)
        rows.append(f"| `{name}` | {seconds * 1e3:.0f} ms | {startup['ratio_to_numpy'][name]:.2f}× | "
                    f"{'≤ %g×' % target if target else '—'} |")
    return "\n".join(rows) + "\n\n" + _machine(startup)


def first_run_table() -> str | None:
    result = _load("first_run.json")
    if result is None:
        return None
    rows = ["| command | cold (empty numba cache) | warm | cold / warm, wall | cold / warm, CPU |",
            "| --- | --- | --- | --- | --- |"]
    for row in result["rows"]:
        rows.append(f"| {row['command']} | {row['cold_wall']:.1f} s | {row['warm_wall']:.1f} s | "
                    f"**{row['ratio_wall']:.1f}×** | {row['ratio_cpu']:.1f}× |")
    text = ("\n".join(rows) + f"\n\nMedians of {result['rounds']} rounds, each command a whole process "
            "(`python benchmarks/first_run.py`).")
    first = result.get("first_run")
    if first:
        names = {"fused serial": "the whole step on one thread", "fused parallel": "the whole step on two threads",
                 "compiled serial": "the force balance and stages (a dense kernel's; a dipping or 3-D fault's step "
                                    "loads a part of them) on one thread",
                 "compiled parallel": "the force balance on two threads"}
        cases = "; ".join(f"{names.get(row['case'], row['case'])}, {row['compile']:.3g} s to compile and "
                          f"{row['load']:.2g} s to load" for row in first["rows"])
        text += (" A 2-D run's estimate adds what its process still owes before the first step (the first run's "
                 f"CPU less a second run's, medians of {first['rounds']} rounds, "
                 f"`python benchmarks/first_run.py --part first-run`): {cases}.")
    return f"{text} {_machine(result)}"


def renewal_coverage_table() -> str | None:
    """The renewal fits' 95 % ranges: coverage of the true mean and aperiodicity (renewal_coverage.py)."""
    result = _load("renewal_coverage.json")
    if result is None:
        return None
    rows = ["| model | aperiodicity | mean: pivotal | mean: bootstrap | aperiodicity: pivotal | aperiodicity: bootstrap |",
            "| --- | --- | --- | --- | --- | --- |"]
    for row in result["rows"]:
        pivotal, bootstrap = row["coverage"]["pivotal"], row["coverage"]["bootstrap"]
        rows.append(f"| {row['model']} | {row['aperiodicity']:g} | **{100 * pivotal['mean']:.1f} %** | "
                    f"{100 * bootstrap['mean']:.1f} % | **{100 * pivotal['aperiodicity']:.1f} %** | "
                    f"{100 * bootstrap['aperiodicity']:.1f} % |")
    return ("\n".join(rows) + f"\n\n{result['catalogs']} catalogs of {result['events']} events per row, "
            f"{result['draws']} draws each (benchmarks/renewal_coverage.py).")


def chain_example_table() -> str | None:
    """The shipped chain's run and its predictability (chain_example.py): what the chain and classroom pages quote."""
    r = _load("chain_example.json")
    if r is None:
        return None
    low, high = r["b_over_cutoffs"]
    b = (f"b = {r['b_value']:.3g} (GR holds: KS p = {r['gr_p_value']:.2g})" if r["gutenberg_richter"] else
         f"none: not Gutenberg-Richter (KS p = {r['gr_p_value']:.2g}; b moves from {low:.2f} to {high:.2f} with the "
         "cutoff)")
    time_r, slip_r = r["time_predictable"], r["slip_predictable"]
    rows = ["| quantity | value |", "| --- | --- |",
            f"| blocks, events | {r['blocks']}, {r['events']} |",
            f"| magnitudes | {r['magnitude_range'][0]:.2f} to {r['magnitude_range'][1]:.2f} |",
            f"| b-value | {b} |",
            f"| system-size events (half the blocks or more) | {r['system_events']} |",
            f"| CV of their intervals (0 periodic, 1 Poisson) | {r['system_cv']:.2f} |",
            f"| CV of all intervals | {r['all_events_cv']:.2f} ({r['all_events_cv_range'][0]:.2f}-"
            f"{r['all_events_cv_range'][1]:.2f}) |",
            f"| r(slip, the interval after): time-predictable | {time_r['r']:.2f} ({time_r['range'][0]:.2f} to "
            f"{time_r['range'][1]:.2f}): {'yes' if time_r['holds'] else 'no'} |",
            f"| r(the interval before, slip): slip-predictable | {slip_r['r']:.2f} ({slip_r['range'][0]:.2f} to "
            f"{slip_r['range'][1]:.2f}): {'yes' if slip_r['holds'] else 'no'} |"]
    return "\n".join(rows) + f"\n\n`python benchmarks/chain_example.py` ({r['scene']}). {_machine(r)}"


def fault_2d_table() -> str | None:
    result = _load("fault_2d.json")
    if result is None:
        return None
    rows = ["| run | elements | recurrence | surface slip per event | settled (spread) | steps | wall time |",
            "| --- | --- | --- | --- | --- | --- | --- |"]
    for row in result["convergence"] + [result["timed_at_loosest"]]:
        rows.append(f"| BP1, {row['element_size_m']:g} m, {row['years']:g} yr, rtol {row['rtol']:g} | {row['elements']} | "
                    f"{row['recurrence_yr']:.5f} yr | {row['surface_slip_m']:.5f} m | {row['settled']} "
                    f"({row['recurrence_spread']:.1e}) | {row['steps']:,} | {row['wall_s'] / 60:.1f} min |")
    difference = result["difference_coarse_fine"]
    rows.append("")
    rows.append(f"Between the two element sizes: recurrence {difference['recurrence'] * 100:.3f} %, surface slip "
                f"{difference['surface_slip'] * 100:.3f} %. The loosest rtol tested whose recurrence (100 m, "
                f"{result['tolerance_study'][0]['years']:g} yr) stays within 0.1 % of the tightest's: "
                f"{result['loosest_rtol']:g} (relative differences: " + ", ".join(
                    f"{row['rtol']:g}: {row['recurrence_error']:.1e}" for row in result["tolerance_study"]) + ").")
    finer = result.get("finer")
    if finer:
        coarse, fine = finer["sizes_m"]
        rows.append("")
        rows.append(f"{fine:g} m against {coarse:g} m: recurrence {finer['recurrence_difference'] * 100:.4f} %, surface "
                    f"slip {finer['surface_slip_difference'] * 100:.4f} %. Its cost is {finer['cost_ratio']:.2f}× "
                    f"{coarse:g} m's: {finer['steps_ratio']:.2f}× the steps (finer elements resolve faster slip, so the "
                    f"steps through each rupture shorten) and {finer['cost_per_step_ratio']:.2f}× the cost a step, "
                    + ("within" if finer["cost_per_step_ratio"] <= finer["n_log_n_ratio"] else "above")
                    + f" the {finer['n_log_n_ratio']:.2f}× that an N log N product predicts for twice the elements "
                    f"(the {coarse:g} m and {fine:g} m rows at rtol 1e-8 measured on {finer['date']}, one after the "
                    "other on one pinned core; the other rows on the date below).")
    return "\n".join(rows) + "\n\n" + _machine(result)


def fault_2d_qdyn_table() -> str | None:
    result = _load("fault_2d_qdyn.json")
    if result is None:
        return None
    grid = result.get("tolerance_grid") or []
    rows = ["| code, solver | loosest tolerance within 0.1 % of its own converged recurrence | recurrence (its "
            "converged value) | steps | wall time | CPU time | peak memory |",
            "| --- | --- | --- | --- | --- | --- | --- |"]
    for name, code in result["codes"].items():
        timed = code.get("timed")
        study = [row for row in code["study"] if "failed" not in row and row.get("settled")]
        failed = [row for row in code["study"] if "failed" in row]
        converged = min(study, key=lambda row: row["tolerance"])["recurrence_yr"] if study else float("nan")
        failures = (" (failed at " + ", ".join(f"{row['tolerance']:g}" for row in failed) + ": " +
                    failed[0]["failed"].split(":")[0] + ")") if failed else ""
        if timed is None or "failed" in timed:
            rows.append(f"| {name} | none{failures} | | | not timed | | |")
            continue
        rows.append(f"| {name} | {code['setting']:g}{failures} | {timed['recurrence_yr']:.4f} yr ({converged:.4f} yr) "
                    f"| {timed['steps']:,} | {timed['wall_s']:.1f} s | {timed.get('cpu_s', float('nan')):.1f} s | "
                    f"{timed.get('peak_mib', float('nan')):.0f} MiB |")
    rows.append("")
    if result.get("ratio_faultslip_over_best_peer"):
        rows.append(f"faultslip / {result['best_peer']} = **{result['ratio_faultslip_over_best_peer']:.2f}** in wall time, "
                    f"{result.get('cpu_ratio_faultslip_over_best_peer', float('nan')):.2f} in CPU time (target ≤ 0.5). "
                    f"BP1 for {result['years']:g} yr on {result['elements']} elements of "
                    f"{result['element_size_m']:.4g} m; every code's tolerance study ran over "
                    f"{result['tolerance_years']:g} yr on the same grid, {grid[0]:g} to {grid[-1]:g}; each timed run a "
                    f"whole process pinned to core {result.get('pinned_core', 0)}, the codes interleaved over "
                    f"{result.get('rounds', 1)} rounds (order reversed every other round), the medians shown; QDYN "
                    f"commit {(result.get('qdyn_commit') or 'unknown')[:7]}.")
        memory = [f"{name} {code['memory']['short_peak_mib']:.0f} MiB over {code['memory']['short_years']:g} yr and "
                  f"{code['memory']['long_peak_mib']:.0f} MiB over {code['memory']['long_years']:g} yr "
                  f"({code['memory']['growth']:+.1%})" for name, code in result["codes"].items() if code.get("memory")]
        if memory:
            rows.append("")
            rows.append("Peak memory against the simulated span: " + "; ".join(memory) + ".")
    return _peer_closing(rows, result)


def fault_2d_threads_table() -> str | None:
    result = _load("fault_2d_threads.json")
    if result is None:
        return None
    rows = [f"| elements | {result['runs'][0]['years']:g}-yr runs: one / two threads | gain | trial steps near "
            "(pairs) | short runs in pairs, near throughout: median (pairs, range) |", "| --- | --- | --- | --- | --- |"]
    for run in result["runs"]:
        near = run["trial_steps"]["near"]
        steps = f"{near['speedup']:.2f}× ({near['pairs']})" if near["pairs"] else "none near"
        short = run.get("short_runs") or {}
        gains = [pair["gain"] for pair in short.get("pairs", []) if pair["placement"] == "near"]
        pairs = (f"{short['near_median_gain']:.2f}× ({len(gains)}, {min(gains):.2f}-{max(gains):.2f}×)" if gains
                 else "none near throughout")
        rows.append(f"| {run['elements']:,} | {run['one_thread']['wall_s']:.2f} / {run['two_threads']['wall_s']:.2f} s "
                    f"| {run['speedup']:.2f}× | {steps} | {pairs} |")
    share = result["placement"]["share"]
    span = f", {result['started']}-{result['ended']} UTC" if result.get("started") else ""
    years = result["runs"][0].get("short_runs", {}) or {}
    return ("\n".join(rows) + f"\n\nTarget ≥ 1.6×. {result['rounds']} interleaved rounds of whole runs (medians), "
            + (f"pairs of {years['years']:g}-yr runs, " if years else "")
            + f"batches of 100 trial steps through the run's loop; the placement over the run: shared core "
            f"{share['shared core']:.0%}, near {share['near']:.0%}, far {share['far']:.0%}. The same bits on one "
            f"thread and two: {all(run['identical_bits'] for run in result['runs'])}. "
            f"`python benchmarks/fault_2d_threads.py`; {result['machine']}, {result['date']}{span}."
            + _packages(result))


def fault_2d_placement_table() -> str | None:
    result = _load("fault_2d_placement.json")
    if result is None:
        return None
    rows = ["| placement | rounds | private work, the other core busy | private work, a spin barrier after each "
            f"{result.get('chunk_values', 800)} values | a barrier | a line written on one core, read on the "
            f"other | a task's {result['trial_lines']:,} such lines a trial at {result['elements']:,} elements |",
            "| --- | --- | --- | --- | --- | --- | --- |"]
    for name, row in result["classes"].items():
        if row["rounds"]:
            between = row.get("work_between_barriers")
            barrier = row.get("barrier_us")
            rows.append(f"| {name} | {row['rounds']} | {row['private_slowdown']:.2f}× | "
                        + (f"{between:.3f}× | " if between is not None else "not measured | ")
                        + (f"{barrier:.2f} µs | " if barrier is not None else "not measured | ")
                        + f"{row['crossing_ns_per_line']:.1f} ns | {row['trial_crossing_us']:.0f} µs |")
    span = f", {result['started']}-{result['ended']} UTC" if result.get("started") else ""
    return ("\n".join(rows) + f"\n\nEach round kept in the class its round trips before and after agree on. "
            f"`python benchmarks/fault_2d_placement.py`; {result['machine']}, {result['date']}{span}."
            + _packages(result))


def fault_2d_profile_table() -> str | None:
    result = _load("fault_2d_profile.json")
    if result is None:
        return None
    parts = list(result["runs"][0]["inside_the_step_us"])
    rows = ["| elements | a trial step | " + " | ".join(result["runs"][0]["shares"]) + " | "
            + " | ".join(f"inside: {part}" for part in parts) + " |", "| --- " * (2 + len(result["runs"][0]["shares"])
                                                                               + len(parts)) + "|"]
    for run in result["runs"]:
        rows.append(f"| {run['elements']:,} | {run['per_trial_us'] / 1e3:.2f} ms | "
                    + " | ".join(f"{share:.0%}" for share in run["shares"].values()) + " | "
                    + " | ".join(f"{run['inside_the_step_us'][part]:.0f} µs" for part in parts) + " |")
    first = result["runs"][0]
    return ("\n".join(rows) + f"\n\nBP1 over {first['years']:g} yr at rtol {first['rtol']:g} on one pinned core; the "
            "shares split the run by cProfile, the parts inside the step are each timed alone on the run's last state. "
            f"`python benchmarks/fault_2d_profile.py`. {_machine(result)}")


def fault_2d_resolution_table() -> str | None:
    result = _load("fault_2d_resolution.json")
    if result is None:
        return None
    from faultslip.models.fault_2d.analysis import MIN_RESOLUTION, discretisation_error

    levels = [run["resolution"] for run in result["faults"][0]["runs"]]
    rows = ["| fault | W / h* | " + " | ".join(f"{level:.2g} per L_b" for level in levels) + " |",
            "| --- " * (2 + len(levels)) + "|"]
    for fault in result["faults"]:
        cells = [("unsettled" if run["sequence"] == "unsettled" else f"{run['error']:.2%}") for run in fault["runs"]]
        rows.append(f"| {fault['name']} ({fault['scene']}) | "
                    f"{fault['seismogenic_width_m'] / fault['nucleation_size_m']:.2g} | " + " | ".join(cells) + " |")
    nominal = [round(level, 1) for level in levels]  # the designed levels (a size is a whole number of elements)
    rows.append("| declared | | " + " | ".join("refused" if level < MIN_RESOLUTION else
                                                 f"{discretisation_error(level):.2%}" for level in nominal) + " |")
    return ("\n".join(rows) + "\n\nEach run's recurrence against its fault's Richardson limit over the element "
            "sizes; elements per L_b = G D_c / (sigma_n b) rounded. `python benchmarks/fault_2d_resolution.py`. "
            + _machine(result))


def fault_2d_period3_table() -> str | None:
    result = _load("fault_2d_period3.json")
    if result is None:
        return None
    rows = ["| element size | sequence | intervals (yr) | mean (yr) | largest interval error | steps | wall time |",
            "| --- | --- | --- | --- | --- | --- | --- |"]
    for run in result["runs"]:
        errors = run.get("interval_errors")
        rows.append(f"| {run['element_size_m']:g} m | {run['kind']}, period {run['period']} | "
                    + ", ".join(f"{value:.3f}" for value in run["intervals_yr"])
                    + f" | {run['mean_interval_yr']:.4f} | " + (f"{max(errors):.1e}" if errors else "n/a")
                    + f" | {run['steps']:,} | {run['wall_s']:.0f} s |")
    return ("\n".join(rows) + f"\n\n`configs/{result['scene']}` over {result['runs'][0]['years']:g} yr; each "
            f"interval against the {result['runs'][0]['element_size_m']:g} m run's. "
            f"`python benchmarks/fault_2d_period3.py`. {_machine(result)}")


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


def _peer_closing(rows: list, result: dict) -> str:
    """A peer table's end: why QDYN did not run, if it did not, and the machine and date."""
    if not result.get("ratio_faultslip_over_best_peer") and result.get("qdyn_missing"):
        rows.append(f"QDYN was not run on this machine: {result['qdyn_missing']}.")
    return "\n".join(rows) + "\n\n" + _machine(result)


def spring_block_qdyn_table() -> str | None:
    result = _load("spring_block_qdyn.json")
    if result is None:
        return None
    ours = result["faultslip"]
    rows = ["| code, solver | setting | recurrence (error against converged) | wall, median | CPU | peak memory |",
            "| --- | --- | --- | --- | --- | --- |"]
    error = ours.get("recurrence_error")
    cpu, peak = result.get("cpu_s", {}), result.get("peak_mib", {})
    loosest = ours.get("loosest_within")
    rows.append(f"| faultslip `rate-state cycles --cycles 100 --json` ({ours.get('command_integrator') or ours['integrator']}) "
                f"| rtol {ours['rtol']:g} (its default; its own study's loosest within 1e-6: "
                f"{f'{loosest:g}' if loosest else 'none'}) | {ours['recurrence_yr']:.7f} yr"
                f"{f' ({error:.1e})' if error is not None else ''} | **{result['wall_s']['faultslip'] * 1e3:.0f} ms** | "
                f"{cpu.get('faultslip', float('nan')) * 1e3:.0f} ms | {peak.get('faultslip', float('nan')):.0f} MiB |")
    for name, peer in result.get("qdyn", {}).items():
        chosen = next(row for row in peer["study"] if row["accuracy"] == peer["accuracy"])
        for label, wall in result["wall_s"].items():
            if label.startswith(f"QDYN {name},"):
                rows.append(f"| {label} | ACC {peer['accuracy']:g} (loosest within 1e-6) | "
                            f"{chosen['recurrence_yr']:.7f} yr ({chosen['recurrence_error']:.1e}) | {wall * 1e3:.0f} ms | "
                            f"{cpu.get(label, float('nan')) * 1e3:.0f} ms | {peak.get(label, float('nan')):.0f} MiB |")
    rows.append("")
    if result.get("ratio_faultslip_over_best_peer"):
        startup = result.get("startup_s", {})
        rows.append(f"faultslip / the fastest QDYN run ({result['best_peer']}) = "
                    f"**{result['ratio_faultslip_over_best_peer']:.2f}** in wall time (target ≤ 0.5), "
                    f"{cpu.get('faultslip', float('nan')) / cpu.get(result['best_peer'], float('nan')):.2f} in CPU time "
                    f"(the fastest QDYN run's wall time is {result['wall_s'][result['best_peer']] / cpu.get(result['best_peer'], float('nan')):.1f} "
                    f"times its CPU time: its start-up waits rather than computes); "
                    f"against QDYN writing the "
                    f"time series its events come from ({result['fair_peer']}): "
                    f"**{result['ratio_faultslip_over_fair_peer']:.2f}**. {result['cycles']} cycles after spin-up, "
                    f"{result['simulated_years']:.0f} simulated years, each run a whole process pinned to one core, "
                    f"interleaved with the order reversed every other round, median of the repeats; every code's "
                    f"tolerances studied on one grid, 1e-2 to 1e-10; QDYN commit {result.get('qdyn_commit') or 'unknown'}. Where the time goes: "
                    f"faultslip's cycles take {ours['cycles_wall_s'] * 1e3:.0f} ms ({ours['steps']:,} steps), the "
                    f"interpreter {startup.get('python', float('nan')) * 1e3:.0f} ms and numpy's import "
                    f"{(startup.get('python + numpy', float('nan')) - startup.get('python', float('nan'))) * 1e3:.0f} ms; "
                    f"QDYN over one simulated second takes {startup.get('QDYN, 1 s simulated', float('nan')) * 1e3:.0f} ms, "
                    f"its start-up.")
    return _peer_closing(rows, result)


def spring_chain_speed_table() -> str | None:
    result = _load("spring_chain_speed.json")
    if result is None:
        return None
    walls, agree, close = result["baseline_wall_s"], result["events_agreeing"], result["events_within_1e-9"]
    default, few = result["solver"], result["baseline_events"]
    names = {"closed_form_compiled": "closed-form slips, compiled (faultslip's default)",
             "closed_form": "closed-form slips in Python (the same scheme)",
             "DOP853": "slips integrated by scipy's DOP853, rtol 1e-10, terminal events"}
    rows = ["| run | blocks | events | wall time | per event | against the Python closed form |",
            "| --- | --- | --- | --- | --- | --- |",
            f"| {names[default]} | {result['blocks']} | {result['events']:,} | **{result['wall_s']:.2f} s** (target < "
            f"{result['target_s']:g} s) | {result['wall_s'] / result['events'] * 1e3:.3f} ms | |"]
    for name, wall in walls.items():
        same = ("the reference" if name == "closed_form" else
                f"the same blocks in the first {agree[name]} events, start times within 1e-9 in the first {close[name]}")
        rows.append(f"| {names[name]} | {result['blocks']} | {few} | {wall:.3f} s | {wall / few * 1e3:.3f} ms | {same} |")
    rows += ["", f"Compiled / Python closed form = **{result['ratio_over_python_closed_form']:.4f}**, compiled / DOP853 = "
             f"**{result['ratio_over_dop853']:.4f}** (Python closed form / DOP853 = "
             f"{result['ratio_closed_form_over_dop853']:.2f}): the same chain from the same start, interleaved over "
             f"{result['rounds']} rounds, medians; the catalogues agree event for event until the chaotic chain's "
             f"round-off grows. {result['subphases']:,} slip sub-phases in the long run, "
             f"{result['mean_blocks_slipped']:.1f} blocks an event on average; one core (the process pinned)."]
    catalogue = result.get("catalogue")
    if catalogue and catalogue.get("b"):
        low, high = catalogue["b_interval"]
        rows.append("")
        rows.append(f"The long run's catalogue: b = **{catalogue['b']:.3f}** ({low:.3f}–{high:.3f}), magnitudes "
                    f"{catalogue['magnitude_range'][0]:.2f} to {catalogue['magnitude_range'][1]:.2f}, "
                    f"{catalogue['system_events']:,} system-size events (half the blocks or more) whose intervals "
                    f"have a coefficient of variation of {catalogue['recurrence_cv']:.2f}; every block's slip / (V t) "
                    f"from {catalogue['plate_balance'][0]:.6f} to {catalogue['plate_balance'][1]:.6f}, within the "
                    f"{catalogue['plate_balance_bound']:.1e} its stored stretch allows.")
    return "\n".join(rows) + "\n\n" + _machine(result)


def lab_fits_table() -> str | None:
    speed, coverage = _load("posterior_speed.json"), _load("fit_coverage.json")
    if speed is None and coverage is None:
        return None
    rows = ["| measurement | result |", "| --- | --- |"]
    if speed is not None:
        rows.append(f"| posterior of the shipped 5-step raw record ({speed['draws']:,} draws, {speed['walkers']} walkers, "
                    f"{speed['steps']} steps, until converged; `benchmarks/posterior_speed.py`) | faultslip "
                    f"{speed['faultslip_seconds']:.1f} s; emcee with a plain scipy-odeint model on the same work "
                    f"{speed['baseline_seconds']:.1f} s: **{speed['ratio']:.2f}** |")
    if coverage is not None:
        for kind, label in (("covariance", "covariance"), ("bootstrap", "bootstrap (100 resamples)"),
                            ("posterior", "posterior")):
            row = coverage["coverage"][kind]
            rows.append(f"| coverage of the 95 % {label} intervals, {row['a']['cases']} seeded raw records "
                        f"(`benchmarks/fit_coverage.py`) | a {row['a']['coverage']:.1%}, b {row['b']['coverage']:.1%}, "
                        f"D_c {row['critical_slip']['coverage']:.1%} |")
    free = _load("stiffness_free.json")
    if free is not None:
        timing = free["speed"]
        rows.append(f"| the same record's posterior with the **stiffness free** (10,000 draws, until converged; "
                    f"`benchmarks/stiffness_free.py`) | **{timing['medians']['stiffness_free']['wall_s']:.1f} s** "
                    f"(target < {timing['target_s']:g} s), {timing['ratio_free_over_fixed']:.2f} x the baseline, the "
                    f"same posterior with the stiffness fixed ({timing['medians']['stiffness_fixed']['wall_s']:.1f} s) |")
        for kind, label in (("covariance", "least-squares covariance"), ("posterior", "posterior")):
            row = free["coverage"][kind]
            low, high = row["a"]["binomial_95"]
            rows.append(f"| coverage of the 95 % {label} intervals with the stiffness free, {row['a']['cases']} seeded "
                        f"raw records, the stiffness stated within about 30 % (`benchmarks/stiffness_free.py`) | "
                        f"a {row['a']['coverage']:.1%}, b {row['b']['coverage']:.1%}, D_c "
                        f"{row['critical_slip']['coverage']:.1%}, k {row['stiffness']['coverage']:.1%} (a perfect "
                        f"95 % lands in {low:.1%}-{high:.1%} 95 times in 100) |")
    p655 = _load("p655_analysis.json")
    if p655 is not None:
        ups = [w["aging"] for seq in p655["sequences"].values() for w in seq["windows"]
               if w["kind"] == "up" and "a" in w["aging"]]
        differences = [w["a"]["value"] - w["b"]["value"] for w in ups]
        springs = [w["stiffness"]["value"] for w in ups]
        chosen = [w["selection"]["chosen"] for seq in p655["sequences"].values() for w in seq["windows"]
                  if "selection" in w]
        rows.append(f"| Penn State's p655 (a real biax run, pylook's), each of its {len(chosen)} velocity steps fitted "
                    f"with the stiffness and a trend free (`benchmarks/p655_analysis.py`, docs/lab_fits.md) | a - b "
                    f"{min(differences):+.4f} to {max(differences):+.4f} in every up-step (velocity strengthening); "
                    f"k {min(springs):.0f}-{max(springs):.0f} /m; BIC on effective points chooses "
                    + ", ".join(f"{name.replace('_', ' ')} in {chosen.count(name)}" for name in dict.fromkeys(chosen))
                    + " |")
    result = speed or coverage
    return "\n".join(rows) + "\n\n" + _machine(result)


#: the parameters of a rate-and-state fit as docs/lab_fits.md names them
_FIT_NAMES = {"a": "a", "b": "b", "critical_slip": "D_c", "stiffness": "k"}


def fit_coverage_table() -> str | None:
    result = _load("fit_coverage.json")
    if result is None:
        return None
    labels = {"covariance": "covariance (s² (JᵀJ)⁻¹, t quantile)",
              "bootstrap": "bootstrap (100 residual resamples, each refitted)",
              "posterior": "posterior (emcee until converged)"}
    names = list(result["coverage"]["covariance"])
    rows = ["| interval | " + " | ".join(_FIT_NAMES[n] for n in names) + " |", "| --- " * (1 + len(names)) + "|"]
    for kind, label in labels.items():
        rows.append(f"| {label} | " + " | ".join(f"{result['coverage'][kind][n]['coverage']:.1%}" for n in names)
                    + " |")
    every = [row for kind in labels for row in result["coverage"][kind].values()]
    low, high = every[0]["binomial_95"]
    inside = all(low <= row["coverage"] <= high for row in every)
    below = all(row["coverage"] < 0.95 for row in every)
    cases = result["cases"]
    boot = statistics.median(case["bootstrap_seconds"] for case in cases)
    post = statistics.median(case["posterior_seconds"] for case in cases)
    return ("\n".join(rows) + f"\n\nWith {every[0]['cases']} cases, a true 95 % lands in {low:.0%}-{high:.0%} "
            "nineteen times in twenty; " + ("every figure is inside that band" if inside else
                                            "some figures fall outside that band")
            + (", all below 95 %: the intervals are slightly narrow (the detected step times and the speeds measured "
               "from a noisy LVDT are taken as exact, and their errors are not carried)" if below else "")
            + f". A bootstrap case takes {boot:.1f} s and a posterior {post:.1f} s (medians, one core). "
            f"Failures: {result['failures']['bootstrap']} bootstraps, {result['failures']['posterior']} posteriors. "
            f"`python benchmarks/fit_coverage.py`. {_machine(result)}")


def posterior_speed_table() -> str | None:
    result = _load("posterior_speed.json")
    if result is None:
        return None
    return (f"The posterior of `{result['record']}` converged with {result['draws']:,} draws after burn-in "
            f"({result['walkers']} walkers, {result['steps']} steps) in {result['faultslip_seconds']:.1f} s, the "
            f"least-squares start included. The baseline ({result['baseline']}) did the same work in "
            f"{result['baseline_seconds']:.1f} s: **{result['ratio']:.2f}** of its time. Its friction agrees with "
            f"faultslip's to {result['baseline_minus_faultslip_friction_at_the_law']:.1e} at the posterior's median "
            f"law. `python benchmarks/posterior_speed.py`. {_machine(result)}")


def stiffness_free_table() -> str | None:
    result = _load("stiffness_free.json")
    if result is None:
        return None
    lines = []
    for kind, label in (("covariance", "least-squares covariance intervals"), ("posterior", "posterior's intervals")):
        row = result["coverage"][kind]
        lines.append(f"- The {label} with k free cover " + ", ".join(
            f"{_FIT_NAMES[n]} in {row[n]['coverage']:.1%}" for n in row) + f" of {row['a']['cases']} records.")
    low, high = result["coverage"]["covariance"]["a"]["binomial_95"]
    lines.append(f"- A perfect 95 % lands in {low:.1%}-{high:.1%} over {result['coverage']['covariance']['a']['cases']} "
                 "records, 95 times in 100.")
    timing = result["speed"]
    lines.append(f"- **Posterior speed.** {timing['record']}: with k free it converges in "
                 f"{timing['medians']['stiffness_free']['wall_s']:.1f} s on one core, with k fixed in "
                 f"{timing['medians']['stiffness_fixed']['wall_s']:.1f} s: freeing k costs "
                 f"{timing['ratio_free_over_fixed']:.2f}× (target under {timing['target_s']:g} s).")
    return "\n".join(lines) + f"\n\n`python benchmarks/stiffness_free.py`. {_machine(result)}"


def _figure(value: float) -> str:
    """A fitted or scored number as a reader wants it: whole from 100 up, three figures below."""
    return f"{value:.0f}" if abs(value) >= 100 else f"{value:.3g}"


def _pressure(label: str) -> float:
    """A p655 sequence's normal stress from its label ("75 MPa"), Pa."""
    return float(label.split()[0]) * 1e6


def _speeds(window: dict) -> str:
    return " → ".join(f"{value:.4g}" for value in window["speeds_um_s"]) + " µm/s"


def p655_found_table() -> str | None:
    result = _load("p655_analysis.json")
    if result is None or not all("steady_steps" in seq for seq in result["sequences"].values()):
        return None
    rows = ["| at | what | faultslip finds |", "| --- | --- | --- |"]
    for label, seq in result["sequences"].items():
        for hold in seq["holds"]:
            rows.append(f"| {label} | a hold, {hold['start_s']:.1f}-{hold['start_s'] + hold['hold_time_s']:.1f} s | "
                        f"{hold['hold_time_s']:.1f} s; healing Δμ = {hold['healing']:.4f}, relaxation "
                        f"{hold['relaxation']:.3f} |")
        fastest = max(seq["speeds_um_s"])
        for step in seq["steady_steps"]:
            difference = step["a_minus_b"]
            # a step into or out of the fastest segment carries that segment's slip weakening in its level
            biased = " (biased by the fast segment's slip weakening)" if fastest in step["speeds_um_s"] or max(
                step["speeds_um_s"]) >= 0.99 * fastest else f" (velocity {'strengthening' if difference > 0 else 'weakening'})"
            rows.append(f"| {label} | {_speeds(step)} at {step['time_s']:.1f} s | a − b = {difference:+.4f}{biased} |")
    return "\n".join(rows) + f"\n\n`python benchmarks/p655_analysis.py`. {_machine(result)}"


def _narrowness(fit: dict) -> tuple[float, float] | None:
    """(lag-one autocorrelation, how many times too narrow) from a fit's note, where it has one."""
    for note in fit.get("notes", []):
        found = re.search(r"autocorrelation ([\d.]+)\).*?about ([\d.]+) times too narrow", note)
        if found:
            return float(found.group(1)), float(found.group(2))
    return None


def p655_steps_table() -> str | None:
    result = _load("p655_analysis.json")
    if result is None:
        return None
    rows = ["| step | a | b | D_c | k (1/m) | c (1/m) | rms |", "| --- | --- | --- | --- | --- | --- | --- |"]
    ups, narrow = [], []
    for label, seq in result["sequences"].items():
        for window in seq["windows"]:
            fit = window["aging"]
            if window["kind"] == "hold" or "a" not in fit:
                continue
            value = {name: fit[name]["value"] for name in ("a", "b", "critical_slip", "stiffness", "trend")}
            rows.append(f"| {label}, {_speeds(window)} | {value['a']:.3g} | {value['b']:.3g} | "
                        f"{_figure(value['critical_slip'] * 1e6)} µm | {value['stiffness']:.0f} | {value['trend']:+.2g} | "
                        f"{fit['residual_rms']:.1e} |")
            if window["kind"] == "up":
                ups.append((label, value))
            if _narrowness(fit):
                narrow.append(_narrowness(fit))
    differences = [v["a"] - v["b"] for _, v in ups]
    springs = [v["stiffness"] for _, v in ups]
    machine_stiffness = [v["stiffness"] * _pressure(label) / 1e12 for label, v in ups]
    lines = [f"- **a − b is {min(differences):+.4f} to {max(differences):+.4f} in every up-step**"
             + (": the gouge is velocity strengthening, as the steady levels alone said (above)."
                if min(differences) > 0 else ".")]
    lines.append(f"- **The stiffness.** The up-steps give k = {min(springs):.0f}-{max(springs):.0f} /m, K = k sigma_n "
                 f"= {min(machine_stiffness):.2f}-{max(machine_stiffness):.2f} MPa/µm.")
    posteriors = result.get("posteriors") or {}
    if posteriors:
        said = []
        for label, posterior in posteriors.items():
            parameters = posterior["parameters"]
            worst = max(p["r_hat"] for p in parameters.values())
            scale = {"critical_slip": 1e6}  # D_c in µm
            said.append(f"at {label} " + ", ".join(
                f"{_FIT_NAMES[n]} {_figure(parameters[n]['median'] * scale.get(n, 1))}"
                f"{' µm' if n == 'critical_slip' else ' /m' if n == 'stiffness' else ''} "
                f"({_figure(parameters[n]['credible_95'][0] * scale.get(n, 1))}-"
                f"{_figure(parameters[n]['credible_95'][1] * scale.get(n, 1))})"
                for n in ("a", "b", "critical_slip", "stiffness")) + f" (R-hat ≤ {worst:.2f}, {posterior['seconds']:.0f} s)")
        lines.append("- **The posteriors of the two slow up-steps** (k and the trend free, emcee until converged): "
                     + "; ".join(said) + ".")
    if narrow:
        rhos, factors = [n[0] for n in narrow], [n[1] for n in narrow]
        lines.append(f"- **Those intervals are too narrow, and the fit says so.** The residuals are correlated (lag-one "
                     f"autocorrelation {min(rhos):.2f}-{max(rhos):.2f}); every interval treats the samples as "
                     f"independent, so for AR(1) noise it is about √((1+ρ)/(1−ρ)) too narrow: {min(factors):.2g} to "
                     f"{max(factors):.2g} times here. Each fit's notes state its factor.")
    joint = result.get("joint_slow_up_steps")
    if joint:
        shared = joint["shared"]
        lines.append("- **A joint fit of the two slow up-steps** (a, b, D_c shared; mu0, k and c each its own) gives "
                     f"a {shared['a']['value']:.3g}, b {shared['b']['value']:.3g}, D_c "
                     f"{shared['critical_slip']['value'] * 1e6:.3g} µm.")
    return ("\n".join(rows) + "\n\n" + "\n".join(lines) + "\n\n`python benchmarks/p655_analysis.py`. "
            + _machine(result))


def p655_laws_table() -> str | None:
    result = _load("p655_analysis.json")
    if result is None:
        return None
    rows = ["| window | chosen | ΔBIC of the others | effective points (of) |", "| --- | --- | --- | --- |"]
    favour = {"up": [], "down": []}
    for label, seq in result["sequences"].items():
        for window in seq["windows"]:
            chosen = window.get("selection")
            if not chosen:
                continue
            others = sorted(((law, value) for law, value in chosen["delta_bic"].items() if law != chosen["chosen"]),
                            key=lambda item: (item[1] is None, item[1] or 0))
            said = ", ".join(f"{law.replace('_', ' ')} {_figure(value)}" if value is not None else
                             f"{law.replace('_', ' ')}: no converged fit" for law, value in others)
            rows.append(f"| {label}, {_speeds(window)} | {chosen['chosen'].replace('_', ' ')} | {said} | "
                        f"{chosen['effective_points']:,.0f} ({chosen['points']:,}) |")
            aging, slip = chosen["delta_bic"].get("aging"), chosen["delta_bic"].get("slip")
            if aging is not None and slip is not None:
                favour[window["kind"]].append(aging - slip)  # > 0: the slip law fits better
    lines = []
    for kind, values in favour.items():
        if values:
            slip_wins = sum(value > 0 for value in values)
            lines.append(f"- {kind.capitalize()}-steps: the slip law beats the aging law in {slip_wins} of {len(values)} "
                         "(ΔBIC aging − slip: " + ", ".join(("+" if value > 0 else "") + _figure(value)
                                                            for value in values) + ").")
    return ("\n".join(rows) + "\n\nBetween the one-state laws:\n\n" + "\n".join(lines)
            + f"\n\n`python benchmarks/p655_analysis.py`. {_machine(result)}")


YEAR_S = 365.25 * 86400.0
#: What seed 003 prints for the 1906 example (quoted from the seed, beside what faultslip computes).
SEED_003_PRINTS = {"normal_stress": "385 bar", "stiffness": "4.4 psi/in",
                   "loading_rate": "5 × 10^-10 1/s (a factor-10 slip)", "stress_drop_slip": "254 in = 21.2 ft",
                   "slip_per_event": "—", "recurrence_period": "(formula only, eq. 5-5)", "stress_drop": "—",
                   "moment": "— (Song et al. 2008: 7.9e20, Mw 7.9)",
                   "inverse": "0.079, mu_m = 0.57 (printed with K = 3.25 for 3.52)", "radiation": "—"}


def seed_1906_table() -> str | None:
    result = _load("docs_numbers.json")
    if result is None:
        return None
    seed, quote = result["seed_003_1906"], SEED_003_PRINTS
    feet, bar = 0.3048, 1e5
    slip_phase = seed["slip_per_event"] - seed["stress_drop_slip"]
    rows = ["| quantity | faultslip | seed 003 printed |", "| --- | --- | --- |",
            f"| sigma_n = tau / mu_so | {seed['normal_stress'] / bar:.2f} bar | {quote['normal_stress']} |",
            f"| K = G / D | {seed['stiffness']:.5g} Pa/m = {seed['stiffness'] * 0.0254 / 6894.757:.5g} psi/in | "
            f"{quote['stiffness']} |",
            f"| theta_dot = K V / sigma_n | **{seed['loading_rate']:.4g} 1/s** | {quote['loading_rate']} |",
            f"| stress-drop slip alpha = x1 − x2 (eq. 2-19) | {seed['stress_drop_slip']:.4g} m = "
            f"{seed['stress_drop_slip'] / feet:.4g} ft | {quote['stress_drop_slip']} |",
            f"| slip per event, ∫u dt = alpha + V t_slip | {seed['slip_per_event']:.4g} m (V t_slip = "
            f"{slip_phase:.1e} m) | {quote['slip_per_event']} |",
            f"| recurrence T = alpha / V + t_slip | {seed['recurrence_period'] / YEAR_S:.4g} yr | "
            f"{quote['recurrence_period']} |",
            f"| stress drop K alpha | {seed['stress_drop'] / bar:.3g} bar | {quote['stress_drop']} |",
            f"| M0, Mw (L = 270 mi, H = 12 km) | {seed['seismic_moment']:.3g} N m, Mw {seed['moment_magnitude']:.3g} | "
            f"{quote['moment']} |",
            f"| granite inverse: mu_so − mu_m | {result['granite_inverse']['friction_drop']:.3g}, mu_m = "
            f"{result['granite_inverse']['kinetic_friction']:.3f} | {quote['inverse']} |",
            f"| with radiation damping (c_s = sqrt(G/rho), so zeta = {result['radiation']['damping_ratio']:g}) | "
            f"{result['radiation']['slip_per_event']:.3g} m, {result['radiation']['recurrence_period'] / YEAR_S:.3g} yr "
            f"| {quote['radiation']} |"]
    return "\n".join(rows) + f"\n\n`python benchmarks/docs_numbers.py`. {_machine(result)}"


def _signed(value: float, digits: int = 2) -> str:
    return f"{value:+.{digits}f}".replace("-", "−")


def empirical_1906_table() -> str | None:
    result = _load("docs_numbers.json")
    if result is None:
        return None
    rows = ["| relation | expects | prediction | ratio or difference | z |", "| --- | --- | --- | --- | --- |"]
    for row in result["empirical_1906"]:
        slip = row["quantity"] == "slip_per_event"
        expected, predicted = row["expected"]["value"], row["predicted"]["value"]
        shown = (lambda v: f"{v:.3g} m") if slip else (lambda v: f"{v:.3g}")
        compared = f"{row['ratio']:.3g}" if slip else _signed(predicted - expected)
        z = _signed(row["z_score"]) if row["z_score"] is not None else "–"
        rows.append(f"| {row['relation'].replace('1994 ', '').replace('2010 ', '')} | {shown(expected)} | "
                    f"{shown(predicted)} | {compared} | {z} |")
    return "\n".join(rows) + f"\n\n`python benchmarks/docs_numbers.py`. {_machine(result)}"


def parkfield_table() -> str | None:
    result = _load("docs_numbers.json")
    if result is None:
        return None
    c = result["parkfield_catalog"]
    year = lambda entry: entry["value"] / YEAR_S  # noqa: E731
    pair = lambda values, scale=1.0: f"{values[0] / scale:.3g}-{values[1] / scale:.3g}"  # noqa: E731
    horizon_year = int(c["as_of"][:4]) + int(float(c["horizon"].split()[0]))
    rows = ["| | observed | predicted (seed law, D = 6 km) |", "| --- | --- | --- |",
            f"| mean interval | {year(c['observed_mean_interval']):.3g} yr (CV {c['observed_cv']:.2f}, "
            f"{c['observed_intervals']} intervals) | {year(c['predicted_recurrence']):.3g} yr ({c['recurrence_ratio']:.3g} "
            f"times; percentile {min(c['lognormal_percentile'], c['bpt_percentile']):.0%} or more of both fits) |"]
    for name, label in (("lognormal", "lognormal fit"), ("bpt", "BPT fit")):
        rows.append(f"| {label} | mean {year(c[name + '_mean']):.3g} yr (95 %: "
                    f"{pair(c[name + '_mean_95']['value'], YEAR_S)}), aperiodicity {c[name + '_aperiodicity']:.2f} "
                    f"({pair(c[name + '_aperiodicity_95'])}) | |")
    rows.append(f"| P(event by {horizon_year}), as of {c['as_of']} | {c['bpt_probability']:.2f} (BPT; 95 %: "
                f"{c['bpt_probability_95'][0]:.2f}-{c['bpt_probability_95'][1]:.2f}) | |")
    rows.append(f"| magnitude | M {c['observed_max_magnitude']:.1f} | Mw {c['predicted_magnitude']:.3g} (slip "
                f"{c['predicted_slip_per_event']['value']:.3g} m) |")
    widths = ["| D | slip per event | recurrence | Mw |", "| --- | --- | --- | --- |"]
    for row in result["parkfield_widths"]:
        widths.append(f"| {row['zone_width']} | {row['slip_per_event_m']:.3g} m | {row['recurrence_s'] / YEAR_S:.3g} yr | "
                      f"{row['moment_magnitude']:.3g} |")
    return ("\n".join(rows) + f"\n\nThe seed law does not reproduce Parkfield: its recurrence is "
            f"{c['recurrence_ratio']:.2g} times the observed mean and its magnitude {c['magnitude_difference']:.2g} units "
            "too large, because its slip per event scales with σ_n D Δμ / G. The prediction depends on the choice of D "
            "(the same scene at three widths):\n\n" + "\n".join(widths)
            + f"\n\n`python benchmarks/docs_numbers.py`. {_machine(result)}")


def california_scaling_table() -> str | None:
    result = _load("docs_numbers.json")
    if result is None or "california_sources" not in result:
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
    result = _load("docs_numbers.json")
    if result is None or "rupture_sets" not in result:
        return None
    rows = ["| branch | sections | ruptures allowed | with a rate | multi-fault with a rate | slip rates released to | "
            "b of the solved MFD | shape misfit |", "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for branch in result["rupture_sets"]:
        rows.append(f"| {branch['relation']} | {branch['sections']} | {branch['ruptures']} | {branch['ruptures_with_rate']} "
                    f"| {branch['multi_fault_ruptures_with_rate']} | {branch['budget_error']:.1e} | "
                    f"{branch['b_value']:.3f} | {branch['shape_misfit']:.2g} |")
    return "\n".join(rows) + f"\n\n`python benchmarks/docs_numbers.py`. {_machine(result)}"


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


def critical_comparison_table() -> str | None:
    result = _load("docs_numbers.json")
    if result is None or "critical_comparison" not in result:
        return None
    table = result["critical_comparison"]
    exact = np.asarray(table["critical_loading_rate"]["value"], float)  # 1/s, presets x damping ratios
    seed = np.asarray(table["seed_appendix_I_loading_rate"]["value"], float)
    ratio = seed / exact  # presets x damping ratios
    said = [f"at zeta = {zeta:g} the seed's is {ratio[:, k].min():.3g}-{ratio[:, k].max():.3g} times the exact value"
            for k, zeta in enumerate(table["damping_ratio"])]
    return (table["markdown"].rstrip() + "\n\nSeed over exact, over the presets: " + "; ".join(said)
            + f".\n\n`python benchmarks/docs_numbers.py` (`faultslip critical --table`). {_machine(result)}")


def rate_state_examples_table() -> str | None:
    result = _load("docs_numbers.json")
    if result is None or "rate_state_examples" not in result:
        return None
    rows = ["| scene | K / K_c | slip per event | recurrence | the 2-D fault's recurrence by the model error | "
            "seed law beside it |", "| --- | --- | --- | --- | --- | --- |"]
    for row in result["rate_state_examples"]:
        low, high = row["recurrence_range"]
        within = f"{low / YEAR_S:.3g} yr or more" if high is None else f"{low / YEAR_S:.3g}-{high / YEAR_S:.3g} yr"
        rows.append(f"| {row['scene']} | {row['stiffness_ratio']:.3g} | {row['slip_per_event']:.3g} m | "
                    f"{row['recurrence_period'] / YEAR_S:.3g} yr | {within} (model error {row['model_error']:.2f}) | "
                    f"{row['seed_law_slip_per_event']:.3g} m every {row['seed_law_recurrence_period'] / YEAR_S:.3g} yr "
                    f"(slip ratio {row['slip_per_event'] / row['seed_law_slip_per_event']:.2f}) |")
    return "\n".join(rows) + f"\n\n`python benchmarks/docs_numbers.py`. {_machine(result)}"


#: The synthetic phone record's inputs (configs/example_phyphox.csv, docs/classroom.md): band stiffness (N/m), phone
#: mass (kg), pulling speed (m/s) and the friction drop mu_s - mu_k it was generated with.
PHONE_RECORD_INPUTS = {"stiffness": 8.0, "mass": 0.2, "speed": 0.02, "friction_drop": 0.10}


def classroom_record_table() -> str | None:
    result = _load("docs_numbers.json")
    if result is None or not result.get("classroom_record"):
        return None
    record, given = result["classroom_record"], PHONE_RECORD_INPUTS
    low, high = record["friction_drop_range"]
    omega = math.sqrt(given["stiffness"] / given["mass"])
    rows = ["| quantity | recovered | the model's input |", "| --- | --- | --- |",
            f"| slips | {record['events']} in {record['duration']:.0f} s, every {record['recurrence']:.3g} s "
            f"(CV {record['recurrence_cv']:.1g}) | |",
            f"| μs − μk | {record['friction_drop']:.3f} (range {low:.3f}-{high:.3f}) | {given['friction_drop']:.2f} |",
            f"| ω of the band | {record['angular_frequency']:.3g} 1/s | √({given['stiffness']:g}/{given['mass']:g}) = "
            f"{omega:.3g} 1/s |",
            f"| pulling speed V | {record['pull_speed'] * 100:.2g} cm/s | {given['speed'] * 100:g} cm/s |",
            f"| slip distance | {record['slip_distance'] * 1e3:.1f} mm measured, {record['slip_distance_model'] * 1e3:.1f} "
            "mm from the fitted model | |"]
    return "\n".join(rows) + f"\n\n`python benchmarks/docs_numbers.py`. {_machine(result)}"


def seed_000_addendum_table() -> str | None:
    result = _load("docs_numbers.json")
    if result is None or "seed_000_addendum" not in result:
        return None
    values = result["seed_000_addendum"]
    rows = ["| quantity | seed 000 prints | computed |", "| --- | --- | --- |",
            f"| E' for E = 210 kN/mm², ν = 0.3 | 115 kN/mm² | {values['contact_modulus'] / 1e9:.5g} kN/mm² |",
            f"| H' = 0.25 E' √(2.37/58.7) | 5.78 kN/mm² | "
            f"{values['elastic_contact_hardness_at_printed_modulus'] / 1e9:.4g} kN/mm² (with E' = 115) |",
            f"| ψ with H = 208 kgf/mm² | 11.3 | {values['plasticity_index']:.4g} |",
            f"| real area for 30 N at p_c = 280 N/mm² | 0.107 mm² | {values['real_area'] * 1e6:.4g} mm² |"]
    return "\n".join(rows) + f"\n\n`python benchmarks/docs_numbers.py`. {_machine(result)}"


def rough_slider_table() -> str | None:
    """Seed 000's AD1.3 runs beside what the seed prints (docs/surfaces.md)."""
    result = _load("docs_numbers.json")
    if result is None or "rough_slider" not in result:
        return None
    values = result["rough_slider"]
    scene, smaller, softer, flat = values["runs"]
    slip_frequency = lambda run: 1.0 / (2.0 * run["slip_duration"])  # noqa: E731 (a half period per slip)
    swing = lambda run: f"{run['peak_to_peak_swing'] * 1e3:.3g} mm"  # noqa: E731
    rows = ["| | seed 000 | computed |", "| --- | --- | --- |",
            f"| real area at rest, 30 N on H = 2.04e9 Pa | 0.0147 mm² | "
            f"{scene['area_fraction_at_rest']:.3g} mm² (of 1 mm² nominal) |",
            f"| √(k/M)/2π, k = 12.66e3 N/m and 6e3 N/m | 23.1 Hz, 16 Hz | {scene['natural_frequency']:.4g} Hz, "
            f"{softer['natural_frequency']:.4g} Hz |",
            f"| μ_s = p_s / H for 6.0e8 / 2.04e9 | \"0.34\" | {scene['static_friction_model']:.3f} (the seed's "
            "arithmetic slip; its break-away displacement gives 0.32) |",
            f"| c from 0.8 to 0.4 (fig. AD4) | smaller stick-slip | smaller: {swing(scene)} to {swing(smaller)} "
            "peak-to-peak |",
            f"| k from 12.66e3 to 6e3 N/m (fig. AD5) | slip-time frequency 20 to 14 Hz (×0.70) | "
            f"{slip_frequency(smaller):.3g} to {slip_frequency(softer):.2g} Hz "
            f"(×{slip_frequency(softer) / slip_frequency(smaller):.2f}); larger stick-slip ({swing(softer)}) |",
            f"| c = 0 | (the map-based chapter 5 model is erratic) | no weakening: μ(u) = μ_s, a harmonic swing "
            f"of 2V/ω = {swing(flat)} |"]
    note = (f"The seed's slips last about a half period (20 Hz against 23.1 Hz natural); the scene's last longer "
            f"({slip_frequency(scene):.3g} Hz), because its friction falls less: "
            f"{100 * values['friction_fall_at_peak_speed']:.1f} % at {values['peak_speed']:g} m/s. Each run is "
            f"`faultslip simulate configs/rough_surface_seed000.toml` (a {values['synthetic_size']} × "
            f"{values['synthetic_size']} Gaussian stand-in, RMS {values['synthetic'][0]}, correlation length "
            f"{values['synthetic'][1]}) with its spring and c replaced.")
    return "\n".join(rows) + f"\n\n{note}\n\n`python benchmarks/docs_numbers.py`. {_machine(result)}"


def _quasi_harmonic():
    result = _load("docs_numbers.json")
    return (None, None) if result is None or "quasi_harmonic" not in result else (result, result["quasi_harmonic"])


def quasi_harmonic_error_table() -> str | None:
    """Averaging's measured error over eps^2 per curve (docs/quasi_harmonic.md)."""
    result, values = _quasi_harmonic()
    if values is None:
        return None
    rows = ["| curve | eps measured over | error / eps² |", "| --- | --- | --- |"]
    for curve, measured in values["error_over_eps_squared"].items():
        low, high = measured["small_parameter"]
        spread = (f"{measured['lowest']:.3f}" if f"{measured['lowest']:.3f}" == f"{measured['highest']:.3f}"
                  else f"{measured['lowest']:.3f}-{measured['highest']:.3f}")
        rows.append(f"| {curve} | {low:.2g} to {high:.2g} | {spread} |")
    worst = max(error / declared for error, declared in zip(values["measured"]["error"],
                                                             values["measured"]["declared"]))
    return ("\n".join(rows) + f"\n\nThe declared error is 0.1 eps²; the largest measured error is {worst:.2f} of it. "
            "Each is integrated (DOP853 at rtol 1e-10) from the averaged amplitude until the approach to the cycle "
            "has decayed by e^-16, peaks sampled 4096 times a period; the scene's row is the scene at five speeds of "
            f"its band. `python benchmarks/docs_numbers.py`. {_machine(result)}")


def quasi_harmonic_scene_table() -> str | None:
    """configs/vibration_seed002.toml's amplitude, its integration and its band (docs/quasi_harmonic.md)."""
    result, values = _quasi_harmonic()
    if values is None:
        return None
    inch = 0.0254
    rows = ["| quantity | computed |", "| --- | --- |",
            f"| amplitude at {values['speed']}, averaged (eq. 20) | {values['amplitude'] / inch:.4f} in, declared "
            f"error {values['declared_error']:.1e} |",
            f"| eq. (10) integrated for {values['simulated_duration']:.0f} s from 5 % of it (`simulate`) | "
            f"{values['simulated_error']:.1e} from the averaged amplitude (relative) |",
            f"| below this driving speed the cycle's peak speed reaches it: the slider sticks | "
            f"{values['sticks_below'] / inch:.2f} in/s |",
            f"| above this speed r + W f'(v) > 0: steady sliding | {values['steady_above'] / inch:.2f} in/s |"]
    return "\n".join(rows) + f"\n\n`python benchmarks/docs_numbers.py`. {_machine(result)}"


def seed002_figures_table() -> str | None:
    """Where seed 002's Figs. 9-11 branches end, rebuilt in kind (docs/quasi_harmonic.md)."""
    result, values = _quasi_harmonic()
    if values is None:
        return None
    inch, ends, flat = 0.0254, values["seed002_ends"], values["flattening_speeds"]
    rows = ["| | ends at | the curve flattens at |", "| --- | --- | --- |"]
    rows += [f"| curve ({name}) | {ends[name] / inch:.3g} in/s | {flat[name] / inch:.3g} in/s |" for name in "ABCD"]
    rows += [f"| curve (A), damping ×{factor} | {ends[f'A_damping_x{factor}'] / inch:.3g} in/s | |"
             for factor in (1, 2, 4)]
    note = (f"Doubling the damping changes curve (A)'s amplitude at {values['damping_speed'] / inch:g} in/s by "
            f"{100 * (values['damped_amplitude_ratio'] - 1):+.0f} %.")
    return "\n".join(rows) + f"\n\n{note} `python benchmarks/docs_numbers.py`. {_machine(result)}"


def seed002_decay_table() -> str | None:
    """Seed 002's Appendix C recomputed by ``faultslip decay`` beside what it prints (docs/lab_fits.md)."""
    result = _load("docs_numbers.json")
    if result is None or "seed002_decay" not in result:
        return None
    values, inch, pound_force = result["seed002_decay"], 0.0254, 4.4482216152605
    mass_imperial = values["mass"] * inch / pound_force  # lb s^2 / in
    rows = ["| quantity | faultslip | seed 002 prints |", "| --- | --- | --- |",
            f"| decay constant Delta = ln(1.225) × 19.9 / 10 | {values['decay_constant']:.5g} 1/s | 0.404 rad/sec |",
            f"| natural frequency sqrt(omega_d² + Delta²) | {values['natural_frequency']:.6g} rad/s | (19.9 × 2 pi) |",
            f"| damping ratio Delta / omega_n | {values['damping_ratio']:.3g} | — |",
            f"| mass M = k / omega_n² | {values['mass']:.4g} kg = {mass_imperial:.5g} lb s²/in (weight "
            f"{values['mass_weight'] / pound_force:.4g} lb) | \"M = 1.76 lb\" |",
            f"| damping coefficient r = 2 M Delta | {values['damping_coefficient'] * inch / pound_force:.5g} lb s/in | "
            "\"0.00368 lb.in/sec\" |"]
    return "\n".join(rows) + f"\n\n`python benchmarks/docs_numbers.py`. {_machine(result)}"


#: Leonard's (2010) Table 6 as printed: Mw - log10 A and Mw - (5/3) log10 L, by setting.
LEONARD_PRINTED = {"strike-slip": (3.99, 4.17), "dip-slip": (4.00, 4.24), "stable-continental": (4.19, 4.32)}


def leonard_table_6_table() -> str | None:
    result = _load("docs_numbers.json")
    if result is None or "leonard_table_6" not in result:
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


def classroom_table() -> str | None:
    result = _load("classroom_redraw.json")
    if result is None:
        return None
    rows = ["| `faultslip classroom`, a knob change in the slider lab | median | 95th percentile | target |",
            "| --- | --- | --- | --- |",
            f"| server: the physics the callback runs ({result['server_ms']['settings']} settings) | "
            f"{result['server_ms']['median']:.0f} ms | {result['server_ms']['p95']:.0f} ms | — |"]
    browser = result.get("browser_ms")
    if isinstance(browser, dict):
        rows.append(f"| headless Chromium: knob to new data | {browser['data_arrived']['median']:.0f} ms | "
                    f"{browser['data_arrived']['p95']:.0f} ms | — |")
        rows.append(f"| headless Chromium: knob to the painted frame ({browser['changes']} changes) | "
                    f"{browser['painted']['median']:.0f} ms | {browser['painted']['p95']:.0f} ms | ≤ 100 ms |")
    else:
        rows.append(f"| headless Chromium | {result.get('browser')} | | |")
    return "\n".join(rows) + "\n\n" + _machine(result)


def animation_table() -> str | None:
    result = _load("animation.json")
    if result is None:
        return None
    ours, theirs = result["medians"]["faultslip"], result["medians"]["matplotlib"]
    rows = ["| `faultslip animate`, one frame of the 1906 GIF | wall | CPU |", "| --- | --- | --- |",
            f"| faultslip (layout once, still parts drawn once, moving artists blitted, one GIF palette) | "
            f"{ours['wall_s_per_frame'] * 1e3:.0f} ms | {ours['cpu_s_per_frame'] * 1e3:.0f} ms |",
            f"| matplotlib's PillowWriter on the same frames (the animation before issue 43) | "
            f"{theirs['wall_s_per_frame'] * 1e3:.0f} ms | {theirs['cpu_s_per_frame'] * 1e3:.0f} ms |",
            f"| speed-up (target ≥ 10×, issue 45: ≥ 20×) | **{result['speed_up']:.1f}×** | {result['cpu_speed_up']:.1f}× |"]
    return ("\n".join(rows) + f"\n\nMedians of {result['pairs']} interleaved pairs of {result['frames']} frames "
            f"(`python benchmarks/animation_speed.py`), {result['machine']}, {result['date']}." + _packages(result))


def ladder_table() -> str | None:
    """The one slider's corrected answers and 95 % ranges against held-out 2-D faults (ladder_calibration.py)."""
    result = _load("ladder_held_out.json")
    if result is None:
        return None
    names = {"recurrence": "recurrence", "mean_slip": "slip per event, mean over the rupture zone",
             "surface_slip": "surface slip per event (surface-breaking faults)"}
    rows = ["| quantity | held-out 2-D faults inside the 95 % range | mean half-width | median bias, block "
            "uncorrected | median bias, corrected |", "| --- | --- | --- | --- | --- |"]
    for key, line in result["summary"].items():
        rows.append(f"| {names[key]} | {line['holds']} of {line['held_out']} ({100 * line['coverage']:.0f} %) | "
                    f"±{100 * line['mean_half_width']:.0f} % | {100 * line['median_bias_uncorrected']:+.0f} % | "
                    f"{100 * line['median_bias_corrected']:+.1f} % |")
    fresh = result.get("fresh")
    if fresh:
        for key, line in fresh["summary"].items():
            rows.append(f"| {names[key]}, **fresh draw** | {line['holds']} of {line['held_out']} "
                        f"({100 * line['coverage']:.0f} %) | ±{100 * line['mean_half_width']:.0f} % | | |")
    outside = sum(bool(row["outside"]) for row in result["rows"])
    budget = result["budget"]
    fresh_note = ""
    if fresh:
        spent = fresh["budget"]
        fresh_note = (f"The fresh draw: {fresh['faults']} faults of a third draw (seed {fresh['seed']}, `python "
                      f"benchmarks/ladder_designs.py --fresh {fresh['faults']}`), run after the ranges were fitted and "
                      f"shipped and read against them as they are, "
                      f"{sum(bool(row['outside']) for row in fresh['rows'])} of them outside the box"
                      + (f", {fresh['left_out_unsettled']} left out unsettled" if fresh["left_out_unsettled"] else "")
                      + (f"; the cost model estimated their CPU at {spent['ratio_min']:.2f} to {spent['ratio_max']:.2f}× "
                         f"what they used, {spent['within_2x']} of {spent['runs']} within 2×" if spent["runs"] else "")
                      + ". ")
    return ("\n".join(rows) + f"\n\n{len(result['rows'])} held-out faults drawn at random over the box "
            f"(`python benchmarks/ladder_designs.py`, then `benchmarks/ladder_calibration.py`), {outside} of them "
            f"outside it (no range declared). " + fresh_note
            + (f"Before each of the {budget['runs']} runs of `ladder_designs.py` (calibration and held out), the cost model now declared "
               f"estimated its CPU: {budget['ratio_min']:.2f} to {budget['ratio_max']:.2f}× what it used (median "
               f"{budget['ratio_median']:.2f}×), {budget['within_2x']} of {budget['runs']} within 2×"
               + (f"; on the {held['runs']} held-out faults, whose steps it was not fitted on, {held['within_2x']} "
                  f"of {held['runs']} ({held['ratio_min']:.2f} to {held['ratio_max']:.2f}×)"
                  if (held := budget.get("held_out")) and held["runs"] else "")
               + (f" ({budget['estimated_by_older_models']} runs estimated by older models are left out)"
                  if budget.get("estimated_by_older_models") else "") + ". " if budget["runs"] else "")
            + _machine(result))


def ladder_limits_table() -> str | None:
    """What limits the one slider's range: the two kinds of 2-D sequence (ladder_calibration.py) and how the kind
    and the recurrence move with D_c on the faults where both kinds occur (ladder_regimes.py)."""
    result = _load("ladder_held_out.json")
    if result is None or "limits" not in result:
        return None
    limits = result["limits"]
    names = {"recurrence": "recurrence", "mean_slip": "slip per event, mean over the rupture zone"}
    rows = ["| quantity | residual sd, all faults | mean residual: every event breaks the zone / partial events "
            "interleave | residual sd within each kind | held out, if told the kind: inside the 95 % range, mean "
            "half-width | a Gaussian process on the groups, held out: inside, mean half-width; told the kind |",
            "| --- | --- | --- | --- | --- | --- |"]
    for key, name in names.items():
        line = limits[key]
        rows.append(f"| {name} | {line['residual_sd_all']:.3f} | {line['mean_residual_single']:+.3f} / "
                    f"{line['mean_residual_interleaving']:+.3f} | {line['residual_sd_single']:.3f} / "
                    f"{line['residual_sd_interleaving']:.3f} | {100 * line['told_kind_coverage']:.0f} % of "
                    f"{line['told_kind_held_out']}, ±{100 * line['told_kind_mean_half_width']:.0f} % | "
                    + (f"{100 * gp['coverage']:.0f} %, ±{100 * gp['mean_half_width']:.0f} %; "
                       f"{100 * gp['told_kind_coverage']:.0f} %, ±{100 * gp['told_kind_mean_half_width']:.0f} % |"
                       if (gp := line.get("gaussian_process")) else "not run |"))
    named = limits["kind_named_from_groups"]
    text = ("\n".join(rows) + f"\n\nResiduals of ln(2-D / block) after the correction. Partial events interleave "
            f"(at least {limits['partial_share']:g} per system-size event) on {limits['calibration_interleaving']} of "
            f"{limits['calibration_faults']} calibration faults and {limits['held_out_interleaving']} of "
            f"{limits['held_out_faults']} held-out ones. A logistic regression on the groups, fitted on the "
            f"calibration faults, names the kind of {named['right']} of {named['held_out']} held-out faults"
            + (f", and a held-out fault's {named['nearest_neighbours']} nearest calibration faults in the groups (k by "
               f"leave-one-out) name {named['right_by_neighbours']}" if "right_by_neighbours" in named else "")
            + f"; always guessing the commoner kind names {named['always_the_commoner']}. The Gaussian process "
            "(a squared-exponential kernel with a length per group, and noise, fitted by marginal likelihood) is a "
            "nonlinear fit of the same groups.")
    # every range in the table: the linear fit told the kind, the Gaussian process without and with it
    fits = [(limits[key]["told_kind_coverage"], limits[key]["told_kind_mean_half_width"]) for key in names]
    fits += [(gp[prefix + "coverage"], gp[prefix + "mean_half_width"]) for key in names
             if (gp := limits[key].get("gaussian_process")) for prefix in ("", "told_kind_")]
    reached = sum(coverage >= 0.95 and half <= 0.25 for coverage, half in fits)
    text += (f" Of the {len(fits)} ranges above, {reached or 'none'} {'reaches' if reached <= 1 else 'reach'} 95 % "
             "of the held-out faults inside at a mean half-width of ±25 % or less.")
    if all("learning_curve" in limits[key] for key in names):
        def widths(key, fit):
            return ", ".join(f"±{100 * point[fit + '_mean_half_width']:.0f} %" for point in limits[key]["learning_curve"])

        curve = limits["recurrence"]["learning_curve"]
        sizes = ", ".join(str(point["faults"]) for point in curve[:-1])
        unlimited = [limits[key]["unlimited_designs_half_width"] for key in names]
        text += (f" Fitted on random subsets of {sizes} of the {curve[-1]['faults']} calibration faults "
                 f"({curve[0]['draws']} draws each) and on all of them, the held-out recurrence range's mean half-width is "
                 f"{widths('recurrence', 'linear')} (the Gaussian process's {widths('recurrence', 'gaussian_process')}); "
                 f"the slip's {widths('mean_slip', 'linear')} ({widths('mean_slip', 'gaussian_process')}). With unlimited "
                 f"designs the declared range would tend to ±{100 * unlimited[0]:.0f} % (recurrence) and "
                 f"±{100 * unlimited[1]:.0f} % (slip), the residual's own spread"
                 + (": more designs of this kind do not bring it to ±25 %." if min(unlimited) > 0.25 else "."))
    if "narrowest" in limits:
        low = limits["narrowest"]
        rec, slip = low["recurrence"], low["mean_slip"]
        floor = min(low[key][fit] for key in names for fit in ("unseen", "refitted", "by_band", "by_band_told_kind"))
        text += (" Set with the 2-D answers in hand, the narrowest 95 % ranges of these groups are "
                 + ("all wider than ±25 %" if floor > 0.25 else f"as narrow as ±{100 * floor:.0f} %")
                 + f": one width about the shipped centre holding 95 % of the {rec['unseen_faults']} unseen faults (held out and "
                 f"fresh) is ±{100 * rec['unseen']:.0f} % (recurrence) and ±{100 * slip['unseen']:.0f} % (slip); the "
                 f"correction refitted on all {rec['refitted_faults']} faults, ±{100 * rec['refitted']:.0f} % and "
                 f"±{100 * slip['refitted']:.0f} % of its own residuals; a width of its own in each of "
                 f"{low['bands']} bands of W/h*, ±{100 * rec['by_band']:.0f} % and ±{100 * slip['by_band']:.0f} % on "
                 f"average; and told each fault's kind as well, ±{100 * rec['by_band_told_kind']:.0f} % and "
                 f"±{100 * slip['by_band_told_kind']:.0f} %. These bounds are not ranges anyone could declare: they "
                 "use the answers.")
    regimes = _load("ladder_regimes.json")
    if regimes is not None:
        summary = regimes["summary"]
        factors = ", ".join(f"{100 * (f - 1):+.0f} %" for f in regimes["factors"] if f != 1.0)
        kinds = " or ".join(f"{kind} (period {period})" if kind == "periodic" else kind
                             for kind, period in summary["widest"]["sequences"])
        text += (f" Rerun with D_c moved by {factors} (`python benchmarks/ladder_regimes.py`), the "
                 f"{summary['faults']} held-out faults whose W/h* lies in {regimes['mixed_width_over_nucleation'][0]:g}-"
                 f"{regimes['mixed_width_over_nucleation'][1]:g}, where both kinds occur, change kind on "
                 f"{summary['kind_changed']}. Their recurrence moves by at most {100 * summary['median_largest_change']:.1f} % "
                 f"on the median fault, and by up to {100 * summary['largest_change']:.0f} % where the sequence changes "
                 f"({summary['widest']['name']}'s runs are {kinds}). The partial events of their unmoved runs ({summary['partial_events']}) start a median "
                 f"{summary['partial_hypocentre_median']:.2f} W below the zone's top and break a median "
                 f"{100 * summary['partial_broken_median']:.0f} % of it.")
        if "starts" in regimes:
            text += " " + _starts_sentence(regimes["starts"])
    return text + " " + _machine(result)


def _starts_sentence(block: dict) -> str:
    """What the held-out faults do from other starts (ladder_regimes.py --part start)."""
    summary = block["summary"]
    speeds = " and ".join(f"{factor:g}" for factor in block["initial_speeds_over_plate_rate"])

    def reached(entry):
        kind = (f"another period-{entry['period']} cycle" if entry["sequence"] == "periodic" else "no settled cycle")
        return (f"{entry['name']} (period {entry['usual_period']} from the usual start; from {entry['start']:g} times "
                f"the plate rate, {kind}, its mean interval {100 * entry['largest_change']:+.0f} %)")

    elsewhere = "; ".join(reached(entry) for entry in summary["elsewhere"])
    return (f"Rerun from other starts, every element in steady state at {speeds} times the plate rate "
            f"(`python benchmarks/ladder_regimes.py --part start`), {summary['same_answer']} of the "
            f"{summary['settled_from_usual_start']} held-out faults that settle from the usual start settle to the "
            f"same cycle (recurrence within {summary['same_answer_within']:g})"
            + (f"; {len(summary['elsewhere'])} do not, and are multistable: {elsewhere}" if summary["elsewhere"] else "")
            + f". The kind changes on {summary['kind_changed']} of {summary['faults']}; the "
            f"{summary['unsettled_from_usual_start']} that do not settle move their mean interval by up to "
            f"{100 * summary['unsettled_largest_change']:.0f} %. A fault's answer can depend on its start, which no "
            "range built on its friction and geometry can know.")


def ladder_escalations_table() -> str | None:
    """Escalations up the ladder: the budget's estimate against the CPU used (ladder_escalations.py), on the draw
    the per-step cost was not fitted on (seed 68001) where it has been run."""
    result = _load("ladder_escalations_held_out.json")
    if result is None:
        return None
    rows = ["| fault | elements | 2-D runs | estimated | CPU used | estimate / CPU | CPU a step / fitted |",
            "| --- | --- | --- | --- | --- | --- | --- |"]
    for row in sorted(result["rows"], key=lambda r: r["design"]["name"]):
        name = f"| {row['design']['name']} (W/h* {row['design']['width_over_nucleation']:.2f}) | {row['elements']} | "
        if "refused" in row:
            rows.append(name + "refused before it ran, in one sentence | | | | |")
            continue
        rows.append(name + f"{row.get('runs', 1)} | {row['estimated_seconds']:.1f} s | {row['cpu_time']:.1f} s | "
                    f"{row['estimated_seconds'] / row['cpu_time']:.2f} | {_step_speed(row):.2f} |")
    summary = result["summary"]
    refused = summary.get("refused", 0)
    return ("\n".join(rows) + f"\n\n{summary['within_2x']} of {summary['escalations']} escalations within 2x (median "
            f"{summary['ratio_median']:.2f}, {summary['ratio_min']:.2f} to {summary['ratio_max']:.2f})"
            + (f", {refused} refused before any work, in one sentence" if refused else "") + "; "
            f"`python benchmarks/ladder_escalations.py --seed {result.get('seed', 68000)}`"
            f"{' (a draw the per-step cost never saw)' if result.get('seed', 68000) != 68000 else ''}. "
            + _further_draws() + "The last column is each escalation's CPU a step (its runs' steps, its first run's "
            "loading of the compiled step included) over the per-step CPU the cost model was fitted with "
            "(`FAULT_2D_STEP_SECONDS`): above 1, the machine ran the steps slower than when the model was fitted "
            f"(median {statistics.median(_step_speed(r) for r in result['rows'] if 'refused' not in r):.2f} here), "
            "which the estimate does not measure. "
            f"{_machine(result)}")


def _step_speed(row: dict) -> float:
    """An escalation's CPU a step over the fitted per-step CPU: each unsettled run is rerun twice as long, so its
    runs took ``steps`` (the last's) times (2^runs - 1) / 2^(runs - 1) steps."""
    from faultslip.models.fault_2d import cost

    c0, c1, _ = cost.FAULT_2D_STEP_SECONDS
    steps = row["steps"] * (2 ** row["runs"] - 1) / 2 ** (row["runs"] - 1)
    return row["cpu_time"] / steps / (c0 + c1 * row["elements"])


def _further_draws() -> str:
    """Further draws of escalations the cost model never saw (ladder_escalations_second_draw.json, then
    ladder_escalations_third_draw.json), a sentence each."""
    text = ""
    for ordinal, name in (("second", "ladder_escalations_second_draw.json"), ("third", "ladder_escalations_third_draw.json")):
        result = _load(name)
        if result is None:
            continue
        summary = result["summary"]
        text += (f"A {ordinal} unseen draw (`--seed {result['seed']}`): {summary['within_2x']} of "
                 f"{summary['escalations']} within 2x ({summary['ratio_min']:.2f} to {summary['ratio_max']:.2f}, median "
                 f"{summary['ratio_median']:.2f})"
                 + (f"; {summary['refused']} refused before any work, in one sentence" if summary.get("refused") else "")
                 + ". ")
    return text


def seas_bp3_table() -> str | None:
    result = _load("seas_bp3.json")
    if result is None:
        return None
    rows = ["| scene | element | period (faultslip, FDRA) | settled intervals vs FDRA | slip at 7.5 km vs FDRA | "
            "surface offsets vs FDRA (-16, 0+, +16 km) | vs our finest | declared (interval) | CPU per simulated yr |",
            "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for case, data in result["cases"].items():
        for run in data["runs"]:
            peer = run["against_peer"]
            offsets = ", ".join(f"{peer['surface_offset_difference'][name]:.2%}" for name in ("n16", "p0", "p16"))
            finest = run.get("settled_interval_difference_from_finest")
            rows.append(f"| {case} | {run['element_size_m']:g} m ({run['elements']}) | {peer['period'][0]}, "
                        f"{peer['period'][1]} | {peer['settled_interval_difference']:.2%} | "
                        f"{peer['settled_slip_difference']:.2%} | {offsets} | "
                        f"{'-' if finest is None else format(finest, '.2%')} | "
                        f"{run['declared_resolution_error']['interval']:.2%} | {run['cpu_s_per_year']:.3g} s |")
    peer = next(iter(result["cases"].values()))["peer"]
    files = "; ".join(f"{data['peer']['code']} ({', '.join(data['peer']['modelers'])}): "
                      + ", ".join(data["peer"]["files"]) for data in result["cases"].values())
    # a step's cost on each rung at the same element count (BP1's steps over its first 150 yr, BP3's over 1500 yr: the
    # work a step does is the same but for the stress product, dense here and by FFT there); benchmarks/
    # plane_strain_step.py times the dense step alone
    runs = {}  # the less loaded of the two scenes' runs at each element count (they ran beside other work)
    for data in result["cases"].values():
        for run in data["runs"]:
            best = runs.get(run["elements"])
            if best is None or run["cpu_s"] / run["steps"] < best["cpu_s"] / best["steps"]:
                runs[run["elements"]] = run
    antiplane = ", ".join(
        f"{row['elements']} elements {row['cpu_s_per_year'] * row['years'] / row['steps'] * 1e3:.2g} ms against "
        f"{runs[row['elements']]['cpu_s'] / runs[row['elements']]['steps'] * 1e3:.2g} ms "
        f"({runs[row['elements']]['cpu_s'] / runs[row['elements']]['steps'] / (row['cpu_s_per_year'] * row['years'] / row['steps']):.0f}x)"
        for row in result["antiplane_cost"] if row["elements"] in runs)
    rtol = {run["rtol"] for data in result["cases"].values() for run in data["runs"]}
    return ("\n".join(rows) + f"\n\nFDRA's files, from the SEAS platform at {peer['element_size']}: {files}. "
            f"faultslip at rtol {', '.join(f'{r:g}' for r in sorted(rtol))}. CPU a step, the antiplane fault (BP1, FFT "
            f"product) against the dipping one (dense): {antiplane}. " + _machine(result))


def dip_model_error_table() -> str | None:
    result = _load("dip_model_error.json")
    if result is None:
        return None
    rows = ["| dip | sense | plane strain: recurrence, slip | antiplane: recurrence, slip | model error |",
            "| --- | --- | --- | --- | --- |"]
    for row in result["rows"] + result["held_out"]:
        held = " (held out)" if "declared" in row else ""
        rows.append(f"| {row['dip']:g}°{held} | {row['sense']} | {row['plane_strain']['recurrence_yr']:.1f} yr, "
                    f"{row['plane_strain']['mean_slip_m']:.2f} m | {row['antiplane']['recurrence_yr']:.1f} yr, "
                    f"{row['antiplane']['mean_slip_m']:.2f} m | {row['model_error']:.1%}"
                    + ((f" (declared {row['declared']:.1%})" if row["declared"] is not None
                        else " (declared: unbounded, outside the measured W / h*)") if held else "") + " |")
    table = result["table"]
    declared = ", ".join(f"{row['dip']:g}° at W / h* {row.get('width_over_nucleation', 0):.3g}: {row['model_error']:.1%}"
                         for row in table["rows"])
    return ("\n".join(rows) + f"\n\nDeclared (the largest of both senses, times {table['margin']:g}): {declared}. "
            f"Held-out faults: {sum(r['declared'] is not None and r['covered'] for r in table['held_out'])} of "
            f"{len(table['held_out'])} within a declared bound, "
            f"{sum(r['declared'] is None for r in table['held_out'])} outside the measured W / h* (unbounded there). "
            + _machine(result))


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


def seas_bp5_table() -> str | None:
    result = _load("seas_bp5.json")
    if result is None:
        return None
    peer = result["peer"]
    rows = ["| squares | elements | squares per L_b | interval | vs the finest | declared | second arrival vs "
            "tandem | interval vs tandem | slips vs tandem (events 1-3) | CPU | wall | peak memory |",
            "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for run in result["runs"]:
        against = run.get("against_tandem")
        slips = ", ".join(f"{v:+.1%}" for v in against["event_slips"]) if against else "-"
        rows.append(f"| {run['element_size_m']:g} m | {run['elements']} | {run['resolution']:.3g} | "
                    f"{run['last_interval_yr']:.2f} yr | {run['interval_difference_from_finest']:+.2%} | "
                    f"{run['declared_error']:.2%} | "
                    + (f"{against['second_arrival']:+.2%} | {against['interval']:+.2%} | " if against else "- | - | ")
                    + f"{slips} | {run['cpu_s']:.0f} s | {run['wall_s']:.0f} s | "
                    f"{run['peak_memory_bytes'] / 2**30:.2f} GiB |")
    fit = result.get("fit")
    declared = (f"Declared: {fit['margin']:g} x {fit['scale']:.3g} r^-{fit['order']:.2f} of the interval, r the squares "
                "per L_b, through the two coarsest sizes' differences from the finest. " if fit else "")
    return ("\n".join(rows) + f"\n\nEach size's last interval between system-size events (the sequence settles "
            f"after the first, which the nucleation patch starts at t = 0; the finest ran "
            f"{min(result['runs'], key=lambda r: r['element_size_m'])['years']:g} yr). " + declared
            + f"tandem (4000 m elements of degree 4) at (0 km, 10 km): second arrival "
            f"{peer['second_arrival_yr']:.2f} yr, interval {peer['interval_yr']:.2f} yr (third arrival within "
            f"{peer['third_arrival_half_gap_yr']:.2f} yr of the rows read), slips "
            + ", ".join(f"{v:.3f}" for v in peer["event_slips_m"]) + " m; the rows read and their file are in "
            "benchmarks/data/bp5_tandem_excerpts.txt. " + _machine(result))


def fault_3d_operator_table() -> str | None:
    result = _load("fault_3d_operator.json")
    if result is None:
        return None
    rows = ["| grid | squares | operator | product | dense product | dense matrix | error vs dense |",
            "| --- | --- | --- | --- | --- | --- | --- |"]
    for kind, family in result["families"].items():
        for row in family["rows"]:
            dense = row.get("dense_product_s")
            rows.append(f"| {kind} {row['strike']} x {row['dip']} | {row['elements']} | {row['bytes'] / 1e6:.3g} MB | "
                        f"{row['product_s'] * 1e3:.3g} ms | "
                        + (f"{dense * 1e3:.3g} ms ({dense / row['product_s']:.1f}x) | {row['dense_bytes'] / 1e6:.3g} MB | "
                           f"{row['relative_error']:.1e} |" if dense is not None else "- | - | - |"))
    slopes = "; ".join(f"{kind}: memory N^{family['memory_exponent']:.2f}, product N^{family['product_exponent']:.2f}"
                       for kind, family in result["families"].items())
    cold = result["cold_warm"]
    threads = result.get("bp5_threads")
    whole = (f" SEAS BP5-QD at 1000 m over 1800 yr: {threads['pairs'][0]['default']['wall_s']:.0f} s wall, "
             f"{threads['pairs'][0]['default']['cpu_s']:.0f} s CPU, peak memory "
             f"{threads['pairs'][0]['default']['peak_memory_bytes'] / 2**30:.2f} GiB; with BLAS held to one thread "
             f"the run takes {threads['wall_ratio']:.2f}x the wall time (median of {len(threads['pairs'])} "
             "interleaved pairs)." if threads else "")
    return ("\n".join(rows) + f"\n\nGrowth (least squares in log-log): {slopes}. Largest error against the dense "
            f"product: {result['largest_relative_error']:.1e}. The small 3-D fault's first run in a fresh process "
            f"(imports, compiled kernels loaded, operator assembled): {cold['cold']['wall_s']:.1f} s against "
            f"{cold['warm']['wall_s']:.1f} s warm ({cold['ratio']:.2f}x)." + whole + " " + _machine(result))


def fault_3d_model_error_table() -> str | None:
    result = _load("fault_3d_model_error.json")
    if result is None:
        return None
    rows = ["| patch L / W (measured) | W | burial | 3-D: recurrence, slip (sequence) | 2-D: recurrence, slip | "
            "model error |", "| --- | --- | --- | --- | --- | --- |"]
    scale = result["scale"]
    for row in result["rows"] + result["held_out"]:
        held = " (held out)" if "declared" in row else ""
        error = "-" if row["model_error"] is None else f"{row['model_error']:.1%}"
        if held:
            error += (f" (declared {row['declared']:.1%})" if row["declared"] is not None
                      else " (declared: unbounded)")
        rows.append(f"| {row['aspect']:g} ({row['aspect_measured']:.2f}){held} | {row['height_m'] * scale / 1e3:g} km | "
                    f"{row['burial']:.2f} | " + (
                        f"{row['fault_3d']['recurrence_yr'] * scale:.1f} yr, {row['fault_3d']['mean_slip_m'] * scale:.2f}"
                        f" m ({row['fault_3d']['sequence']})" if math.isfinite(row['fault_3d']['recurrence_yr'])
                        else "creeps after the first event" if row['fault_3d']['events'] <= 1
                        else f"{row['fault_3d']['events']} events, too few system-size ones for a recurrence")
                    + f" | {row['fault_2d']['recurrence_yr'] * scale:.1f} yr, "
                    f"{row['fault_2d']['mean_slip_m'] * scale:.2f} m | {error} |")
    held = result["held_out"]
    return ("\n".join(rows) + f"\n\nLengths, recurrences and slips as BP5's (the runs, at 1/{scale:g} scale, times "
            f"{scale:g}). "
            f"Declared: the bounding cells' error times {result['table']['margin']:g} "
            "(faultslip.fault.strike_error). Held-out faults, drawn over the same box: "
            f"{sum(bool(r['covered']) for r in held)} of {len(held)} within a declared bound, "
            f"{sum(r['declared'] is None for r in held)} with none declared (no measured cell bounds them), "
            f"{sum(r['declared'] is not None and not r['covered'] for r in held)} outside one. " + _machine(result))


def fault_3d_starts_table() -> str | None:
    """Whether each 3-D cell's cycle is its own whatever its start (fault_3d_model_error.py --starts)."""
    result = _load("fault_3d_starts.json")
    if result is None:
        return None
    summary, scale = result["summary"], result["scale"]
    odd = [c for c in result["cells"] if c["multistable"] is not False]
    details = "; ".join(
        f"{c['aspect']:g} x {c['height_m'] * scale / 1e3:g} km ({c['set']}): "
        + ", ".join((f"{t * scale:.1f} yr" if math.isfinite(t) else "no recurrence") + f" ({s})"
                    for t, s in zip(c["recurrence_yr"], c["sequences"]))
        + (" (multistable)" if c["multistable"] else "") for c in odd)
    changed = summary["largest_change_one_cycle"]
    return (f"Every cell of the table above ({summary['cells']}, calibration and held out) run again from every element off "
            f"the nucleation patch in steady state at 0.1 and 10 times its start's slip rate, the patch kept faster "
            f"(`python benchmarks/fault_3d_model_error.py --starts`, through `faultslip run --check-starts`): "
            f"{summary['one_cycle']} reach the same cycle from every start"
            + (f" (their recurrences within {changed:.1e})" if changed is not None else "")
            + f", {summary['multistable']} are multistable and {summary['undecided']} undecided (a run did not settle"
            + (f"; {summary['no_recurrence']} of them have too few system-size events for a recurrence from any start"
               if summary.get("no_recurrence") else "") + "); "
            f"on {summary['sequence_changed']}, one start's run settles where another's has not yet."
            + (f" Each start's recurrence (its own, 0.1 and 10 times), as BP5's, where they are not one cycle: {details}."
               if odd else "") + " " + _machine(result))


def family_costs_table() -> str | None:
    result = _load("family_costs.json")
    if result is None:
        return None
    rows = ["| family | cost entry | case | work | CPU | estimate | estimate / CPU |",
            "| --- | --- | --- | --- | --- | --- | --- |"]
    for row in result["rows"]:
        case = row["case"] + (" (held out)" if row["held_out"] else "")
        rows.append(f"| {row['family']} | {row['entry']} | {case} | {row['units']:.4g} | "
                    f"{row['cpu_seconds'] * 1e3:.3g} ms | {row['estimate_seconds'] * 1e3:.3g} ms | "
                    f"{row['ratio']:.2f} |")
    fitted, held = result["summary"]["fitted"], result["summary"]["held_out"]
    return ("\n".join(rows) + f"\n\nEach entry's overhead and seconds per unit of work are fitted (non-negative least "
            f"squares) on the cases not marked held out; {fitted['within_2x']} of {fitted['cases']} fitted and "
            f"{held['within_2x']} of {held['cases']} held-out cases are within 2x (held out: {held['ratio_min']:.2f} "
            f"to {held['ratio_max']:.2f}). CPU is the process's, the median of {result['rounds']} timings after a "
            "warm-up. " + _machine(result))


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
    return ("\n".join(rows) + f"\n\nfaultslip: {first['sections']} sections of about 3 km, solved on the Wells & "
            "Coppersmith (1994) area branch with b = 1; SHERIFS: the logged samples whose files agree with one another "
            "(benchmarks/data/sherifs_example_logs.txt names each file and commit). " + _machine(result))


#: Pages whose generated tables update() writes (the README has none: it is a door).
PAGES = ("docs/benchmarks.md", "docs/results.md", "docs/ladder.md", "docs/reliability.md", "docs/catalogs.md",
         "docs/spring_chain.md", "docs/classroom.md", "docs/dipping_faults.md", "docs/hazard.md",
         "docs/fault_3d.md", "docs/fault_2d.md", "docs/studies.md", "docs/lab_fits.md", "docs/critical_rate.md",
         "docs/rate_state.md", "docs/surfaces.md", "docs/quasi_harmonic.md")


def update(readme: Path | None = None) -> list[str]:
    written = []
    for page in ([readme] if readme is not None else [ROOT / name for name in PAGES]):
        written += _update_page(page)
    return written


def _update_page(readme: Path) -> list[str]:
    text = readme.read_text(encoding="utf-8")
    written = []
    for name, render in (("ladder", ladder_table), ("ladder_limits", ladder_limits_table), ("ladder_escalations", ladder_escalations_table), ("benchmarks", benchmarks_table), ("sweep", sweep_table), ("reliability", reliability_table),
                         ("startup", startup_table), ("fault_2d", fault_2d_table),
                         ("fault_2d_qdyn", fault_2d_qdyn_table), ("fault_2d_threads", fault_2d_threads_table),
                         ("fault_2d_placement", fault_2d_placement_table),
                         ("fault_2d_profile", fault_2d_profile_table),
                         ("fault_2d_resolution", fault_2d_resolution_table),
                         ("fault_2d_period3", fault_2d_period3_table),
                         ("san_andreas_map", san_andreas_map_table),
                         ("fit_coverage", fit_coverage_table), ("posterior_speed", posterior_speed_table),
                         ("stiffness_free", stiffness_free_table), ("p655_found", p655_found_table),
                         ("p655_steps", p655_steps_table), ("p655_laws", p655_laws_table),
                         ("seed_1906", seed_1906_table), ("empirical_1906", empirical_1906_table),
                         ("parkfield", parkfield_table), ("california_scaling", california_scaling_table),
                         ("rupture_sets", rupture_sets_table), ("hazard_chain", hazard_chain_table),
                         ("critical_comparison", critical_comparison_table),
                         ("rate_state_examples", rate_state_examples_table),
                         ("classroom_record", classroom_record_table),
                         ("seed_000_addendum", seed_000_addendum_table), ("leonard_table_6", leonard_table_6_table),
                         ("rough_slider", rough_slider_table),
                         ("quasi_harmonic_error", quasi_harmonic_error_table),
                         ("quasi_harmonic_scene", quasi_harmonic_scene_table),
                         ("seed002_figures", seed002_figures_table), ("seed002_decay", seed002_decay_table),
                         ("spring_block_qdyn", spring_block_qdyn_table),
                         ("spring_chain_speed", spring_chain_speed_table),
                         ("lab_fits", lab_fits_table),
                         ("classroom", classroom_table), ("animation", animation_table),
                         ("first_run", first_run_table), ("renewal_coverage", renewal_coverage_table),
                         ("chain_example", chain_example_table), ("seas_bp3", seas_bp3_table),
                         ("dip_model_error", dip_model_error_table), ("engine_branches", engine_branches_table),
                         ("seas_bp5", seas_bp5_table), ("fault_3d_operator", fault_3d_operator_table),
                         ("fault_3d_model_error", fault_3d_model_error_table),
                         ("fault_3d_starts", fault_3d_starts_table),
                         ("family_costs", family_costs_table), ("sherifs_example", sherifs_example_table)):
        table = render()
        pattern = re.compile(rf"(<!-- table:{name} -->\n).*?(<!-- /table:{name} -->)", re.S)
        if table is not None and pattern.search(text):
            text = pattern.sub(lambda m: m.group(1) + table + "\n" + m.group(2), text)
            written.append(name)
    readme.write_text(text, encoding="utf-8")
    return written


if __name__ == "__main__":
    print("updated README tables:", ", ".join(update()) or "none")
