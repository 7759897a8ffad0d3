"""The benchmarks are one package with one entry point, and --all regenerates every generated docs table
(issue 70): checked here without running them (a full run is hours)."""

from __future__ import annotations

import ast
import os
import re
import subprocess
import sys
from pathlib import Path

from conftest import load_benchmark

ROOT = Path(__file__).resolve().parents[2]


entry = load_benchmark("__main__", "benchmarks_entry")


def _flags(script: str) -> set[str]:
    tree = ast.parse((ROOT / "benchmarks" / f"{script}.py").read_text(encoding="utf-8"))
    return {node.args[0].value for node in ast.walk(tree) if isinstance(node, ast.Call)
            and getattr(node.func, "attr", "") == "add_argument" and node.args
            and isinstance(node.args[0], ast.Constant) and str(node.args[0].value).startswith("--")}


def test_every_generated_table_has_a_producer_that_all_runs():
    """Each results file readme.py renders is written by a run of --all, and every table marker in the pages
    readme.py rewrites has a renderer."""
    source = (ROOT / "benchmarks" / "readme.py").read_text(encoding="utf-8")
    tables = "".join(path.read_text(encoding="utf-8") for path in (ROOT / "benchmarks" / "docs_tables").glob("*.py"))
    rendered = set(re.findall(r'_load\("([^"]+)"\)', tables))
    produced = {out for _, _, _, out in entry.PRODUCERS}
    assert rendered and rendered <= produced, rendered - produced
    renderers = set(re.findall(r'^    "(\w+)": \w+_table,$', tables, flags=re.M))
    assert len(renderers) > 50  # the pattern still finds the registries
    pages = ast.literal_eval(re.search(r"^PAGES = (\(.*?\))$", source, flags=re.M | re.S).group(1))
    for page in pages:
        markers = set(re.findall(r"<!-- table:(\w+) -->", (ROOT / page).read_text(encoding="utf-8")))
        assert markers <= renderers, (page, markers - renderers)


def test_every_producer_is_a_script_and_its_arguments_are_its_own():
    names = set(entry.benchmarks())
    for script, full, short, _ in entry.PRODUCERS:
        assert script in names, script
        given = {word for word in full + short if word.startswith("--")}
        assert given <= _flags(script), (script, given - _flags(script))
    for script, flag in entry.PEERS.items():
        assert flag in _flags(script), (script, flag)


def test_the_entry_point_lists_and_refuses_an_unknown_name():
    listed = subprocess.run([sys.executable, "-m", "benchmarks", "--list"], cwd=ROOT, capture_output=True, text=True)
    assert listed.returncode == 0 and "fault_2d_qdyn" in listed.stdout and "fuzz_second_seed.json" in listed.stdout
    wrong = subprocess.run([sys.executable, "-m", "benchmarks", "fuzzz"], cwd=ROOT, capture_output=True, text=True)
    assert wrong.returncode != 0 and "no benchmark named 'fuzzz'" in wrong.stderr


def test_the_fuzzers_workbook_seed_is_one_the_fit_accepts(tmp_path, cli, monkeypatch):
    """A fuzz kind whose seed is itself refused only ever tests the refusal: the xlsx kind's seed fits."""
    import pytest

    pytest.importorskip("openpyxl")
    monkeypatch.syspath_prepend(str(ROOT / "benchmarks"))  # fuzz.py's sibling modules; undone after the test
    fuzz = load_benchmark("fuzz", "fuzz_under_test")

    (tmp_path / "space").mkdir()
    workspace = fuzz.Workspace(tmp_path / "space")
    workspace.close()  # its full-disk tmpfs (root only) is not this test's: left mounted, pytest cannot remove it
    assert not os.path.ismount(tmp_path / "space" / "full")
    book = tmp_path / "rig.xlsx"
    book.write_bytes(workspace.workbook)
    result = cli("fit", book, "--law", "rate-state", "--stiffness", "200 kN/mm", "--area", "25 cm^2", "--json")
    assert result.code == 0, result.err
    assert 0 < result.json["a"] < result.json["b"]  # the header says a 0.008, b 0.012
