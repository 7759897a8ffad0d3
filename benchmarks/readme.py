"""Write the docs' measured tables from benchmarks/results/*.json (called by ``python -m benchmarks``; or run alone).

    python benchmarks/readme.py

Each table is replaced between ``<!-- table:NAME -->`` and ``<!-- /table:NAME -->`` and states the
machine and date of the run that produced it. Nothing here is typed by hand. The renderers live in
benchmarks/docs_tables/, one module per topic, each listing its tables in ``TABLES``.
"""

from __future__ import annotations

import re
from pathlib import Path

from docs_tables import asperity, dipping_and_3d, fault_2d, hazard, lab, ladder, reliability, seed_law, seeds, speed

ROOT = Path(__file__).resolve().parent.parent

#: Every table's renderer, by the marker name in the pages.
RENDERERS = {name: render for module in (speed, reliability, fault_2d, ladder, dipping_and_3d, hazard, seed_law, lab,
                                          seeds, asperity)
             for name, render in module.TABLES.items()}

#: Pages whose generated tables update() writes (the README has none: it is a door).
PAGES = ("docs/benchmarks.md", "docs/results.md", "docs/ladder.md", "docs/reliability.md", "docs/catalogs.md",
         "docs/spring_chain.md", "docs/classroom.md", "docs/dipping_faults.md", "docs/hazard.md",
         "docs/fault_3d.md", "docs/fault_2d.md", "docs/studies.md", "docs/lab_fits.md", "docs/critical_rate.md",
         "docs/rate_state.md", "docs/surfaces.md", "docs/quasi_harmonic.md", "docs/asperity.md",
         "docs/getting_started.md", "docs/methods.md", "docs/seed_discrepancies.md")


def update(readme: Path | None = None) -> list[str]:
    written = []
    for page in ([readme] if readme is not None else [ROOT / name for name in PAGES]):
        written += _update_page(page)
    return written


def _update_page(readme: Path) -> list[str]:
    text = readme.read_text(encoding="utf-8")
    written = []
    for name, render in RENDERERS.items():
        table = render()
        pattern = re.compile(rf"(<!-- table:{name} -->\n).*?(<!-- /table:{name} -->)", re.S)
        if table is not None and pattern.search(text):
            text = pattern.sub(lambda m: m.group(1) + table + "\n" + m.group(2), text)
            written.append(name)
    readme.write_text(text, encoding="utf-8")
    return written


if __name__ == "__main__":
    print("updated docs tables:", ", ".join(update()) or "none")
