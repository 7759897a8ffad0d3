"""The documentation site builds with warnings as errors, and every gallery example runs (issue: never rot)."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def test_sphinx_builds_the_site_with_the_gallery_executed(tmp_path):
    pytest.importorskip("sphinx_gallery", reason="the docs extra is not installed: pip install '.[docs]'")
    environment = {**os.environ, "MPLBACKEND": "Agg", "FAULTSLIP_DOCS_RERUN": "1"}
    result = subprocess.run([sys.executable, "-m", "sphinx", "-W", "-q", "-d", str(tmp_path / "doctrees"),
                             str(ROOT / "docs"), str(tmp_path / "html")], capture_output=True, text=True,
                            env=environment, timeout=900)
    assert result.returncode == 0, result.stderr[-3000:]
    pages = {p.name for p in (tmp_path / "html").glob("*.html")}
    assert {"index.html", "getting_started.html", "physics.html", "methods.html", "reliability.html",
            "seed_discrepancies.html", "api.html", "classroom.html"} <= pages
    gallery = sorted((tmp_path / "html" / "auto_examples").glob("plot_*.html"))
    assert len(gallery) >= 15
    images = list((tmp_path / "html" / "_images").glob("sphx_glr_plot_*.png"))
    assert len(images) >= 15  # every example drew its figure
    # offline: no page loads a script, a style sheet or a font from the network (MathJax ships with the site)
    import re

    remote = re.compile(r'(?:src|href)="(https?:)?//[^"]+\.(?:js|css|woff2?)(?:\?[^"]*)?"')
    for html in (tmp_path / "html").rglob("*.html"):
        found = remote.search(html.read_text(encoding="utf-8"))
        assert found is None, f"{html.name} loads {found.group(0)} from the network"
    assert "classroom_lab.png" in (tmp_path / "html" / "classroom.html").read_text(encoding="utf-8")
    # the physics page's equations are mathematics for MathJax, not code blocks: eq. 2-18 as the code computes it
    physics = (tmp_path / "html" / "physics.html").read_text(encoding="utf-8")
    assert physics.count('class="math') >= 3 and "\\mu_{so} - \\mu_m" in physics
    assert "mu_s = mu_m + (mu_so - mu_m) / (1 + b theta_dot^d)" not in physics


def test_every_data_example_runs_as_configs_readme_shows_it(tmp_path, cli, monkeypatch):
    """configs/README.md gives each synthetic data file its command and options (record needs the apparatus's
    stiffness and normal load, which once appeared only in a test): every line runs as written."""
    import shlex

    root = Path(__file__).resolve().parents[2]
    text = (root / "configs" / "README.md").read_text(encoding="utf-8")
    block = text.split("```sh", 1)[1].split("```", 1)[0]
    commands = [shlex.split(line) for line in block.splitlines() if line.startswith("faultslip ")]
    assert len(commands) >= 10
    monkeypatch.chdir(tmp_path)  # outputs land here; inputs are named from the repository root
    monkeypatch.setenv("FAULTSLIP_REGISTRY", str(tmp_path / "fits.json"))
    for words in commands:
        args = [str(root / w) if w.startswith("configs/") else w for w in words[1:]]
        result = cli(*args)
        assert result.code == 0, (words, result.err)


def test_the_readmes_python_runs_as_written(tmp_path, monkeypatch):
    """The README's 'From Python' block is what a notebook types first: every line runs, from any folder (its
    scenes and studies are bundled names)."""
    import re

    blocks = re.findall(r"^```python\n(.*?)^```", (ROOT / "README.md").read_text(encoding="utf-8"), re.S | re.M)
    assert blocks
    monkeypatch.chdir(tmp_path)
    for block in blocks:
        exec(compile(block, "README.md", "exec"), {})  # noqa: S102  the README's own code
