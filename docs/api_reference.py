"""Writes docs/api.rst from faultslip/api.py's table: every public name, by topic, with the first line of its
docstring and its autodoc entry, so the reference can never list a name that is not public or miss one.

    python docs/api_reference.py          # rewrite docs/api.rst
    python docs/api_reference.py --check  # exit 1 if docs/api.rst is stale (tests/project/test_architecture.py runs it)
"""

from __future__ import annotations

import inspect
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from faultslip import api  # noqa: E402

OUT = ROOT / "docs" / "api.rst"

INTRO = {
    "faultslip": "The command line's five verbs, the Result every computation returns, the errors and the units. "
                 "``faultslip.run(scene)`` and ``faultslip.simulate(scene)`` take a scene file, a bundled scene's "
                 "name or a scene object of any family; ``run`` also takes a fault's inputs as keywords with units "
                 "(``faultslip.run(lithology=\"granodiorite_water\", zone_width=\"13 mi\", shear_stress=\"250 bar\", "
                 "slip_rate=\"2 in/yr\")``).",
    "io": "Seismology's and the benchmarks' formats: catalogues (QuakeML through obspy), waveforms, SEAS output "
          "files, fit bundles and the bundled example files.",
    "friction": "Friction laws (seed 003's static-friction rate law, Cameron's time-of-stick law), the lithologies "
                "and presets that carry them, saved fits, and fitting the rate law to laboratory data.",
    "lab": "A laboratory's records: rate-and-state fits of velocity steps (with posteriors and law selection), raw "
           "rig files, Look/xlook files and r-file reductions, stick-slip motion records and free decay, "
           "slide-hold-slide healing, rough surfaces and the classroom accelerometer.",
    "models": "Every model family behind one contract (``faultslip.models.families()``), the scene readers, and each "
              "family's own computations and figures.",
    "hazard": "The hazard analyst's functions: regional maps and their fault systems, rupture sets, OpenQuake "
              "source models and jobs, displacement hazard, empirical scaling, magnitude-frequency distributions, "
              "renewal probabilities and catalogue predictability.",
    "plots": "Figures of records, fits, catalogues, surfaces and maps (matplotlib); each family's own figures are "
             "in ``faultslip.models``.",
}

CONTRACT = """
For family authors
------------------

A family outside faultslip registers itself through the ``faultslip.families`` entry point; its contract
(``faultslip.contract``) is a declaration, its parameters and outputs, its sweep, and the conformance check every
family passes.

.. automodule:: faultslip.contract.registry
   :members: declare, Family, method_rows

.. automodule:: faultslip.contract.specs
   :members: Parameter, Output

.. automodule:: faultslip.contract.options
   :members: Option, options_of

.. automodule:: faultslip.contract.cells
   :members: Cells, PerCell
"""


#: Values whose docstring is their type's: what they are, in words.
DESCRIBED = {"faultslip.units": "the unit registry (pint) that every boundary parses with: "
                                "``faultslip.units.Quantity(\"13 mi\")``; SI inside, units in files",
             "faultslip.JULIAN_YEAR": "the year faultslip counts in, the Julian year of 365.25 days, in seconds"}


def _first_line(obj) -> str:
    doc = inspect.getdoc(obj) or ""
    return " ".join(doc.split("\n\n", 1)[0].split()).replace("*", r"\*")


def _directive(qualified: str, obj, indexed: bool) -> str:
    options = "" if indexed else "\n   :noindex:"
    if inspect.isclass(obj):
        return f".. autoclass:: {qualified}\n   :members:{options}"
    return f".. autofunction:: {qualified}{options}"


def render() -> str:
    lines = ["API reference", "=============", "",
             "``import faultslip`` gives the command line's five verbs and what they return; everything else is one "
             "topic down, as pvlib's ``pvlib.iotools`` is: ``faultslip.io``, ``friction``, ``lab``, ``models``, "
             "``hazard`` and ``plots``. One verb per idea: ``read_*`` reads a file and ``parse_*`` "
             "the same from text, ``analyze_*`` measures a record, "
             "``simulate_*`` integrates in time, ``*_figure`` draws. Each name is loaded on first use; the modules "
             "it comes from are internal and may move between releases. The flat names of the previous release "
             "(``faultslip.read_look``) still work for one release, with a FutureWarning naming the new place.",
             "", "This page is written by ``docs/api_reference.py`` from ``faultslip/api.py``.", ""]
    groups = {"faultslip": {f"faultslip.{name}": where for name, where in api.TOP.items()}}
    groups |= {topic: {f"faultslip.{topic}.{name}": where for name, where in names.items()}
               for topic, names in api.TOPICS.items()}
    seen = set()  # an object under two names (faultslip.Result, faultslip.models.Result) is indexed once
    for topic, names in groups.items():
        title = "The top level" if topic == "faultslip" else f"faultslip.{topic}"
        lines += [title, "-" * len(title), "", INTRO[topic], ""]
        objects = {qualified: api.resolve(where) for qualified, where in names.items()}
        for qualified, obj in objects.items():
            lines.append(f"* ``{qualified}``: {DESCRIBED.get(qualified) or _first_line(obj)}")
        lines.append("")
        for qualified, obj in objects.items():
            if qualified not in DESCRIBED:
                lines += [_directive(qualified, obj, indexed=id(obj) not in seen), ""]
                seen.add(id(obj))
    lines += CONTRACT.splitlines()
    return "\n".join(lines).rstrip() + "\n"


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    text = render()
    if "--check" in argv:
        if OUT.read_text(encoding="utf-8") != text:
            print("docs/api.rst is stale: run python docs/api_reference.py", file=sys.stderr)
            return 1
        return 0
    OUT.write_text(text, encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
