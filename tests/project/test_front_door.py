"""The front door (issue 70): a README that is a door, and every command the README and the docs show works as
written, on the base install alone."""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from faultslip.cli.main import build_parser
from faultslip.units import quantity

ROOT = Path(__file__).resolve().parents[2]
PAGES = [ROOT / "README.md"] + sorted((ROOT / "docs").glob("*.md"))
#: Documented commands not run as written, each with why. A command that names a file the clone does not ship
#: (the user's own, written "my_gouge.csv" or "study.toml") or a cluster (SLURM, a dask address) is a pattern.
NOT_RUN = {
    "seas_bp1.toml --output-dir": "SEAS BP1 at 1,600 elements over 1,500 years: a benchmark (benchmarks/fault_2d.py)",
    "seas_bp3_thrust60.toml --output-dir": "SEAS BP3-QD on 1,600 dense elements over 1,500 years (about 1.4 h): a "
                                           "benchmark (benchmarks/seas_bp3.py)",
    "seas_bp5.toml --output-dir": "SEAS BP5-QD on 4,000 squares over 1,800 years, with its SEAS files: a benchmark "
                                  "(benchmarks/seas_bp5.py)",
    "study_bp3_dip.toml": "eight whole BP3 runs at 100 m: a benchmark (benchmarks/dip_model_error.py runs the cells)",
    "--scheduler": "needs a SLURM cluster or a dask scheduler (tests/capabilities/studies/test_slurm.py starts one)",
    "--lithology my_gouge": "needs the user's own fit saved as my_gouge",
}
#: Options whose value is a file the command writes (it need not exist).
OUTPUT_OPTIONS = {"-o", "--bundle", "--plot", "--events", "--nrml", "--time-dependent", "--corner", "--regions",
                  "--map", "--stream", "--export", "--output-dir", "--engine-job"}


def documented_commands() -> list[tuple[str, str]]:
    """(page, command) for every ``faultslip`` line of a shell block, continuation lines joined, comments and
    ``pip install . &&`` prefixes dropped."""
    found = []
    for page in PAGES:
        for block in re.findall(r"```(?:sh|bash|console)\n(.*?)```", page.read_text(encoding="utf-8"), flags=re.S):
            for line in block.replace("\\\n", " ").splitlines():
                line = re.sub(r"^pip install \S+ && ", "", line.strip())
                if not line.startswith("faultslip"):
                    continue
                line = re.sub(r"\s+#.*$", "", line) if "#" in line else line
                found.append((page.name, line.strip()))
    return found


def optional_groups_dropped(command: str) -> str:
    """The command without its ``[...]`` optional groups (innermost first) and alternatives ``a | b`` reduced to
    the first."""
    while re.search(r"\[[^\[\]]*\]", command):
        command = re.sub(r"\s*\[[^\[\]]*\]", "", command)
    return command


def computed_part(words: list[str]) -> tuple[str, ...]:
    """A command's words without the files it writes (each of :data:`OUTPUT_OPTIONS` and its value): two commands
    with the same computed part do the same work, and the one that writes more checks both."""
    kept, skip = [], False
    for word in words:
        if skip:
            skip = False
        elif word in OUTPUT_OPTIONS:
            skip = True
        else:
            kept.append(word)
    return tuple(kept)


def test_the_readme_is_a_door():
    """At most 150 lines; no timestamps, dates or issue numbers in it; a start for each of the four users; every
    link it makes resolves."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    assert len(text.splitlines()) <= 150
    assert not re.search(r"\b20\d\d-\d\d-\d\d\b|\bUTC\b|[Ii]ssue \d+", text)
    for user in ("geophysicist", "hazard analyst", "teacher", "lab"):
        assert re.search(rf"\*\*An? {user}", text, flags=re.I), user
    for target in re.findall(r"\]\(([^)#]+)\)", text):
        if not target.startswith("http"):
            assert (ROOT / target).exists(), target


@pytest.mark.parametrize("page, command", documented_commands())
def test_every_documented_command_parses(page, command):
    """Each command the README and docs show is one the parser takes, options and all (optional groups
    dropped): a renamed option or command fails here first."""
    args = shlex.split(optional_groups_dropped(command))[1:]
    if not args:
        return
    parser = build_parser()
    try:
        parser.parse_args(args)
    except SystemExit as exc:
        pytest.fail(f"{page}: {command!r} does not parse (exit {exc.code})")


def _runnable(command: str) -> str | None:
    """Why ``command`` is not run as written, optional groups dropped (None: it is run)."""
    command = optional_groups_dropped(command)
    if "|" in command or "<" in command or "..." in command or "$(" in command:
        return "a pattern with alternative parts"
    words = shlex.split(command)
    if words[1:2] == ["classroom"] and "--export" not in words:
        return "serves until stopped (tests/capabilities/apps/test_classroom_app.py drives the server)"
    for key, why in NOT_RUN.items():
        if key in command:
            return why
    for before, word in zip(words[1:], words[2:]):
        if before in OUTPUT_OPTIONS or word.startswith("-"):
            continue
        if re.search(r"\.(csv|toml|txt|zip|zarr)$", word) and "/" not in word:
            if not any((ROOT / folder / word).exists() for folder in ("configs", "data")):
                return f"names the user's own file {word}"
        if word.startswith(("/shared", "/scratch")):
            return "names a site's own path"
    return None


def test_the_commands_not_run_are_few_and_each_says_why():
    commands = documented_commands()
    skipped = [(command, _runnable(command)) for _, command in commands if _runnable(command)]
    assert len(commands) >= 50 and len(skipped) <= len(commands) // 2, skipped


@pytest.mark.skipif(os.environ.get("CI") != "true" and not os.environ.get("FAULTSLIP_FRESH_VENV"),
                    reason="builds a fresh venv with 'pip install .' alone: run in CI (.ci/run), or set "
                           "FAULTSLIP_FRESH_VENV=1")
def test_every_readme_and_docs_command_runs_on_the_base_install(tmp_path):
    """A fresh venv with only ``pip install .`` (no extras: no pytest, no dask-jobqueue, no OpenQuake) runs every
    documented command that is not a pattern, in a folder holding the clone's configs/ and data/, in page order
    (so that a --resume follows its run). Each exits 0. A command that needs an extra (Zarr, SLURM, a workbook)
    says which in one sentence and leaves no output."""
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True, timeout=300)
    pip = venv / "bin" / "pip"
    source = tmp_path / "source"
    shutil.copytree(ROOT, source, ignore=shutil.ignore_patterns(".git", "*.so", "__pycache__", "build", "_build",
                                                                "*.egg-info", "auto_examples"))
    def files():
        return {path.relative_to(source): path.read_bytes() for path in source.rglob("*") if path.is_file()}

    before = files()
    _add_a_family(source)  # the scratch copy's new family: its folder and one pyproject line, nothing else
    after = files()
    touched = {path for path in after if before.get(path) != after[path]} | (set(before) - set(after))
    assert touched - {Path("pyproject.toml")} and all(
        path == Path("pyproject.toml") or path.parts[:3] == ("faultslip", "models", "constant_friction")
        for path in touched), touched
    done = subprocess.run([str(pip), "install", "--quiet", str(source)], capture_output=True, text=True, timeout=1500)
    assert done.returncode == 0, done.stderr[-2000:]
    extras = subprocess.run([str(venv / "bin" / "python"), "-c", "import importlib.util as u; "
                             "print(all(u.find_spec(name) is None for name in "
                             "('pytest', 'openquake', 'zarr', 'dask_jobqueue', 'openpyxl')))"],
                            capture_output=True, text=True, check=True)
    assert extras.stdout.strip() == "True", "the base install pulled an extra in"
    work = tmp_path / "work"
    work.mkdir()
    shutil.copytree(ROOT / "configs", work / "configs")
    shutil.copytree(ROOT / "data", work / "data")
    environment = {**os.environ, "PATH": f"{venv / 'bin'}{os.pathsep}{os.environ['PATH']}", "MPLBACKEND": "Agg"}
    environment.pop("PYTHONPATH", None)
    environment["HOME"] = str(tmp_path / "home")  # a fit saved by --name goes to this user's registry
    failures, ran, seen = [], 0, set()
    runnable = [(page, command, shlex.split(optional_groups_dropped(command))) for page, command in
                documented_commands() if _runnable(command) is None]
    # of the commands that do the same work, the one that writes the most runs, where it stands (the others'
    # parsing is test_every_documented_command_parses's): a model-error with --plot checks the one without
    widest = {}
    for _, _, words in runnable:
        key = computed_part(words)
        widest[key] = max(widest.get(key, words), words, key=len)
    for page, command, words in runnable:
        if tuple(words) in seen or widest[computed_part(words)] is not words:
            continue  # a command two pages show runs once
        seen.add(tuple(words))
        if "-o" in words or "--output-dir" in words or "--bundle" in words:
            words.append("--overwrite")  # two pages may write the same example output
        result = subprocess.run(words, cwd=work, env=environment, capture_output=True, text=True, timeout=900)
        ran += 1
        if result.returncode != 0:
            failures.append(f"{page}: {command}: exit {result.returncode}: {result.stderr.strip()[-300:]}")
    assert ran >= 30
    # a command that needs an extra the base install lacks says which in one sentence, and leaves nothing behind
    book = work / "rig.xlsx"
    openpyxl = pytest.importorskip("openpyxl")
    sheet = openpyxl.Workbook()
    sheet.active.append(["time (s)", "friction (1)"])
    sheet.active.append([0.0, 0.6])
    sheet.save(book)
    for words, extra, output in (
            (["faultslip", "sweep", "configs/study_spring_slider.toml", "-o", "extra.zarr"], "faultslip[zarr]",
             "extra.zarr"),
            (["faultslip", "sweep", "configs/study_spring_slider.toml", "-o", "extra.nc", "--scheduler", "slurm"],
             "faultslip[dask]", "extra.nc"),
            (["faultslip", "fit", "--law", "rate-state", str(book), "--stiffness", "1e-2 1/um"], "faultslip[xlsx]",
             None)):
        result = subprocess.run(words, cwd=work, env=environment, capture_output=True, text=True, timeout=300)
        lines = result.stderr.strip().splitlines()
        if result.returncode != 2 or len(lines) != 1 or extra not in lines[0] or \
                (output is not None and (work / output).exists()):
            failures.append(f"needs {extra}: {' '.join(words)}: exit {result.returncode}: {result.stderr[-300:]}")
    # the scratch family, found through its entry point: it runs, sweeps, reproduces and passes check_family
    folder = "faultslip/models/constant_friction"
    for words in (["faultslip", "run", f"{source}/{folder}/example.toml", "--json"],
                  ["faultslip", "sweep", f"{source}/{folder}/study.toml", "-o", "constant.nc", "--overwrite"],
                  ["faultslip", "reproduce", "constant.nc"],
                  [str(venv / "bin" / "python"), "-c", "from faultslip.models.checks import check_family; "
                   f"check_family('constant_friction', '{source}/{folder}/example.toml', "
                   "{'normal_load': ['50 N', '100 N']}, simulate_options={'cycles': 2})"]):
        result = subprocess.run(words, cwd=work, env=environment, capture_output=True, text=True, timeout=900)
        if result.returncode != 0:
            failures.append(f"the scratch family: {' '.join(words)}: exit {result.returncode}: "
                            f"{result.stderr.strip()[-300:]}")
    assert not failures, "\n".join(failures)


def _add_a_family(source: Path) -> None:
    """Add tests/families/constant_friction to a scratch copy as a family of the package: its folder (with its
    example scene and study) under faultslip/models/, and its entry point in pyproject.toml."""
    folder = source / "faultslip" / "models" / "constant_friction"
    shutil.copytree(ROOT / "tests" / "families" / "constant_friction", folder,
                    ignore=shutil.ignore_patterns("__pycache__"))
    for module in folder.glob("*.py"):
        module.write_text(module.read_text(encoding="utf-8").replace("from families.constant_friction",
                                                                     "from faultslip.models.constant_friction"),
                          encoding="utf-8")
    (folder / "example.toml").write_text('family = "constant_friction"\n[slider]\nstiffness = "1e5 N/m"\n'
                                         'normal_load = "100 N"\nmass = "1 kg"\nplatform_speed = "1 mm/s"\n'
                                         '[friction]\nstatic = 0.6\nkinetic = 0.5\n', encoding="utf-8")
    (folder / "study.toml").write_text('[study]\nbase = "example.toml"\n[sweep]\nstatic_friction = [0.6, 0.7]\n'
                                       'platform_speed = ["1 mm/s", "2 mm/s"]\n', encoding="utf-8")
    pyproject = source / "pyproject.toml"
    text = pyproject.read_text(encoding="utf-8")
    group = '[project.entry-points."faultslip.families"]\n'
    assert group in text
    pyproject.write_text(text.replace(group, group + 'constant_friction = "faultslip.models.constant_friction.family"\n'),
                         encoding="utf-8")


@pytest.mark.parametrize("argv, suggestion", [
    (["swep", "study.toml"], "did you mean 'sweep'?"),
    (["rate-state", "cycels", "x.toml"], "did you mean 'cycles'?"),
    (["run", "--tolerence", "0.1"], "did you mean '--tolerance'"),
])
def test_a_mistyped_command_or_option_gets_the_nearest_spelling(cli, argv, suggestion):
    result = cli(*argv)
    assert result.code == 2 and len(result.err.strip().splitlines()) == 1
    assert suggestion in result.err


def test_a_command_far_from_any_lists_them_all(cli):
    result = cli("xyzzy")
    assert result.code == 2 and "choose from run, fault" in result.err and "did you mean" not in result.err


def test_python_dash_m_faultslip_is_the_program():
    """Where the script is not on the PATH (a venv not activated, a notebook's shell), ``python -m faultslip`` is the
    same program: the same answer, and a bad input is still one sentence with exit 2."""
    root = Path(__file__).resolve().parents[2]
    ran = subprocess.run([sys.executable, "-m", "faultslip", "run", "configs/san_andreas_1906.toml", "--json"],
                         cwd=root, capture_output=True, text=True)
    assert ran.returncode == 0, ran.stderr
    import json

    import faultslip

    expected = faultslip.run(root / "configs" / "san_andreas_1906.toml")["recurrence_period"].to("s").magnitude
    assert json.loads(ran.stdout)["recurrence_period"]["value"] == expected
    bad = subprocess.run([sys.executable, "-m", "faultslip", "fault", "--zone-width", "13 parsecs per fortnight",
                          "--slip-rate", "2 in/yr"], cwd=root, capture_output=True, text=True)
    assert bad.returncode == 2 and "Traceback" not in bad.stderr and len(bad.stderr.strip().splitlines()) == 1


def _every_option(parser, path=()):
    """(command path, action, option string) for every option of every command, at any depth."""
    import argparse

    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield from _every_option(sub, path + (name,))
        else:
            for option in action.option_strings:
                yield " ".join(path), action, option


def test_each_shared_option_has_one_meaning_across_commands():
    """The option table (contract.options.COMMON) against every command's parser: --json, --overwrite and
    --allow-large say one thing everywhere; -o is always a file and --output-dir always a folder; an option that
    several commands take is the same kind of option (a switch, a value, a repeatable value) in each."""
    import argparse

    from faultslip.contract.options import COMMON, DEPRECATED, FILE_OPTION, FOLDER_OPTION

    kinds: dict = {}
    for command, action, option in _every_option(build_parser()):
        if action.help == argparse.SUPPRESS:  # an old spelling kept for one release
            assert (command, option) in DEPRECATED, (command, option)
            continue
        if option in COMMON:
            assert action.help == COMMON[option], (command, option, action.help)
        if option == FILE_OPTION:
            assert not re.search(r"\b(director|folder)", action.help or ""), (command, action.help)
        if option == FOLDER_OPTION:
            assert re.search(r"\b(director|folder)", action.help or ""), (command, action.help)
        kind = "switch" if action.nargs == 0 else ("repeatable" if type(action).__name__ == "_AppendAction"
                                                   else "value")
        kinds.setdefault(option, {}).setdefault(kind, []).append(command)
    mixed = {option: found for option, found in kinds.items() if len(found) > 1 and option not in ("-h", "--help")}
    # "only these ..." filters of the evaluation commands repeat where a run's option takes one value
    allowed = {"--method", "--damping-ratio", "--scene", "--ratio", "--preset"}
    assert set(mixed) <= allowed, {option: mixed[option] for option in set(mixed) - allowed}


def test_an_old_spelling_still_works_and_says_what_to_use(cli, tmp_path):
    result = cli("decay", "--stiffness", "70.5 lbf/in", "--ratio", "1.225", "--cycles", "10", "--frequency",
                 "19.9 Hz", "--json")
    assert result.code == 0 and "use --cycles-between" in result.err


def test_the_five_verbs_are_at_the_top_level_and_give_what_the_command_line_gives(cli, tmp_path):
    """faultslip.run, simulate, sweep, fit and map: the API is the product (issue 70, item 4)."""
    import xarray as xr

    import faultslip

    for verb in ("run", "simulate", "sweep", "fit", "map"):
        assert callable(getattr(faultslip, verb)), verb
    out = tmp_path / "map.nc"
    assert cli("map", ROOT / "configs" / "san_andreas_map.toml", "-o", out).code == 0
    dataset = faultslip.map(ROOT / "configs" / "san_andreas_map.toml")
    with xr.open_dataset(out) as written:
        xr.testing.assert_identical(written["slip_per_event"].reset_coords(drop=True),
                                    dataset["slip_per_event"].reset_coords(drop=True))
    fitted = faultslip.fit(ROOT / "configs" / "example_friction_data.csv", bootstrap=20)
    printed = cli("fit", ROOT / "configs" / "example_friction_data.csv", "--bootstrap", "20", "--json")
    assert printed.code == 0 and printed.json["mu_so"] == fitted.values["mu_so"]
    with pytest.raises(faultslip.InputError, match="machine stiffness"):
        faultslip.fit(ROOT / "configs" / "example_velocity_steps.csv", law="rate-state")


def test_both_fits_write_the_schema_every_result_writes(tmp_path):
    """faultslip.fit's results have to_xarray() (issue 70: a computation returns a Result or a documented type
    with to_xarray): every number with its units, the ranges on quantile, the draws on their own dimensions; and
    the Dataset round-trips through netCDF."""
    import numpy as np
    import xarray as xr

    import faultslip

    rate = faultslip.fit(ROOT / "configs" / "example_friction_data.csv", bootstrap=20)
    record = faultslip.fit(ROOT / "configs" / "example_velocity_steps.csv", law="rate-state", stiffness="1e-2 1/um")
    for fitted, draws in ((rate, "bootstrap"), (record, None)):
        dataset = fitted.to_xarray()
        assert all("units" in variable.attrs for variable in dataset.data_vars.values())
        if draws:
            assert dataset[draws].shape == (20, 4)
            np.testing.assert_array_equal(dataset[draws].values, rate.bootstrap)
        dataset.to_netcdf(tmp_path / "fit.nc")
        with xr.open_dataset(tmp_path / "fit.nc") as written:
            assert set(written.data_vars) == set(dataset.data_vars)
    assert rate.to_xarray()["mu_so"].item() == rate.values["mu_so"]
    assert record.to_xarray()["critical_slip"].attrs["units"] == "m"


def test_a_fit_reads_as_a_run_does(cli):
    """A fit's numbers are reached as a run's are: ``fit["critical_slip"]`` a pint Quantity in the unit the report
    gives, the 95 % range a pair, the same numbers as the command's --json (its values in SI)."""
    import faultslip

    record = faultslip.fit(ROOT / "configs" / "example_velocity_steps.csv", law="rate-state", stiffness="1e-2 1/um",
                           bootstrap=0)
    printed = cli("fit", "--law", "rate-state", ROOT / "configs" / "example_velocity_steps.csv", "--stiffness",
                  "1e-2 1/um", "--bootstrap", "0", "--json")
    assert printed.code == 0
    written = printed.json["critical_slip"]
    assert written["units"] == "m" and record["critical_slip"].to("m").magnitude == written["value"]
    low, high = record["critical_slip_95"]
    assert low < record["critical_slip"] < high and str(low.units) == "meter"
    assert "a" in record and "b" in record.keys() and "no_such_value" not in record
    rate = faultslip.fit(ROOT / "configs" / "example_friction_data.csv", bootstrap=0)
    assert rate["b"].magnitude == rate.values["b"]  # b carries s^d, d the fitted exponent
    assert rate["b"].units == quantity(1.0, f"s^{rate.values['d']:.4g}").units
    with pytest.raises(KeyError):
        record["no_such_value"]


def test_run_help_says_the_tolerance_may_move_up_the_ladder(cli):
    result = cli("run", "--help")
    text = " ".join(result.out.split())
    assert "2-D fault of the same scene" in text and "--model" in text
