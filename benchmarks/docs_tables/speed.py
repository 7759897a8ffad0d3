"""Speed against peers and baselines (docs/benchmarks.md, docs/results.md)."""

from __future__ import annotations

from provenance import listed  # one stamp for every results file

from ._common import _load, _machine, _packages, _peer_closing


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


def command_estimates_table() -> str | None:
    """docs/benchmarks.md: each family's command estimate against the CPU its command uses (command_estimates.py):
    runs, simulations, sweeps and maps."""
    result = _load("command_estimates.json")
    if result is None:
        return None
    rows = ["| command | estimate (its run's imports) | CPU used | used / estimate | without the imports |",
            "| --- | --- | --- | --- | --- |"]
    for row in result["cases"]:
        rows.append(f"| `{row['command']}` | {row['estimate_seconds']:.2f} s ({row['import_seconds']:.2f} s) | "
                    f"{row['used_seconds']:.2f} s | {row['used_over_estimate']:.2f} | "
                    f"{row['used_over_estimate_without_imports']:.2f} |")
    cases = len(result["cases"])
    return "\n".join(rows) + (
        f"\n\nEach command a whole process, its CPU from its rusage, medians of {result['rounds']} rounds, the "
        "estimate and the run alternating which goes first (`python benchmarks/command_estimates.py`). The estimate is "
        "`faultslip ... --estimate --json`'s `command_seconds`: the family's cost model, the imports its run needs "
        "(measured by importing them) and the command's start. Within 2x of the CPU used: "
        f"{result['within_2x']} of {cases}; without the run's imports, as estimates were before they counted them, "
        f"{result['within_2x_without_imports']} of {cases}. {_machine(result)}")


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
    return ("\n".join(rows) + f"\n\nEach entry's overhead and seconds per unit of work are fitted (non-negative, least "
            f"squares in log estimate / CPU) on the cases not marked held out; {fitted['within_2x']} of "
            f"{fitted['cases']} fitted and "
            f"{held['within_2x']} of {held['cases']} held-out cases are within 2x (held out: {held['ratio_min']:.2f} "
            f"to {held['ratio_max']:.2f}). CPU is the process's, the median of {result['rounds']} timings after a "
            "warm-up. " + _machine(result))


def machine_speed_table() -> str | None:
    """Each cost group's runs repeated now against its fit (machine_speed.py): the reference work carried to the
    state each group was fitted in."""
    import statistics

    result = _load("machine_speed.json")
    if result is None:
        return None
    rows = ["| cost group | fitted on | runs repeated | CPU then / now, median (range) | reference work then (now x then / now) | now |",
            "| --- | --- | --- | --- | --- | --- |"]
    for name, group in result["groups"].items():
        ratios = [run["then"] / run["now"] for run in group["runs"]]
        rows.append(f"| {name} | `{group['source']}` ({group['source_date']}) | {len(ratios)} | "
                    f"{group['then_over_now']:.2f} ({min(ratios):.2f}-{max(ratios):.2f}) | "
                    f"{group['reference_work_seconds'] * 1e3:.3f} ms | "
                    f"{statistics.median(group['probe_now_seconds']) * 1e3:.3f} ms |")
    return ("\n".join(rows) + "\n\nEach group's runs are its fit's own, repeated with the same work and timed as the "
            "fit timed them (per step where a run counts steps); the reference work (`faultslip.io.machine`) was "
            "probed before and after them. A cost model's seconds are multiplied by the reference work's time on "
            "the estimating machine (the median its machine speed record keeps) over its time then. "
            + _machine(result))


def machine_record_table() -> str | None:
    """The same runs' estimates made with the machine speed record's median, with each process's own probe, and
    with the two weighted as faultslip ships, against their CPU: the run that set the weight and the one that tested
    it (machine_record.py)."""
    from faultslip.io.machine import PROBE_WEIGHT

    runs = [(label, _load(name)) for label, name in (("set the weight", "machine_record.json"),
                                                     ("tested it", "machine_record_held_out.json"))]
    runs = [(label, result) for label, result in runs if result is not None]
    if not runs:
        return None
    rows = ["| run | estimate read from | estimate / CPU, median | range | largest / smallest | sd in ln "
            "| within 1.25x of the median |", "| --- | --- | --- | --- | --- | --- | --- |"]
    for label, result in runs:
        summary = result["summary"]
        for key, name in (("with_record", "the record's median alone"),
                          ("blended", "the median and this process's probe, as shipped"),
                          ("probe_alone", "this process's probe alone (as before the record)")):
            line = summary[key]
            rows.append(f"| {label} | {name} | {line['median']:.2f} | {line['min']:.2f}-{line['max']:.2f} | "
                        f"{line['max_over_min']:.2f} | {line['sd_ln']:.3f} | {line['within_1_25x_of_median']} of "
                        f"{summary['processes']} |")
    first = runs[0][1]
    edits = ", ".join(value.split(" = ")[1].strip('"') for value in first["scene_edits"].values())
    text = (f"Each run: {len(first['rows'])} fresh processes, two at a time, each estimated and ran the same 2-D run "
            f"(`configs/fault_2d_small.toml` at {edits}) on one record that started empty; those whose record held "
            f"at least {first['summary']['settled_readings']} readings are read. A process's run speed follows its "
            "own probe in part: the least-squares weight of the probe beside the median (in logs) was "
            + " and ".join(f"{result['summary']['probe_weight_fit']:.2f} in the run that {label}"
                           for label, result in runs)
            + f"; faultslip ships {PROBE_WEIGHT:.2f} (`PROBE_WEIGHT`). The runs' own speed (CPU over the cost model's "
            "at the anchored machine) spread " + " and ".join(
                f"{result['summary']['run_speed']['sd_ln']:.3f}" for _, result in runs)
            + " (sd in ln): the spread a fixed factor would leave. `python benchmarks/machine_record.py`, then "
            "`--out benchmarks/results/machine_record_held_out.json`. "
            + _machine(runs[-1][1]))
    return "\n".join(rows) + "\n\n" + text


#: The tables this module renders, by the marker name in the pages.
TABLES = {
    "benchmarks": benchmarks_table,
    "sweep": sweep_table,
    "startup": startup_table,
    "first_run": first_run_table,
    "command_estimates": command_estimates_table,
    "spring_block_qdyn": spring_block_qdyn_table,
    "spring_chain_speed": spring_chain_speed_table,
    "lab_fits": lab_fits_table,
    "classroom": classroom_table,
    "animation": animation_table,
    "family_costs": family_costs_table,
    "machine_speed": machine_speed_table,
    "machine_record": machine_record_table,
}
