"""Surface command: faultslip surface (seed 000's rough-surface statistics and contact)."""

from __future__ import annotations

import numpy as np

from faultslip.cli.common import _number, _outputs, _save_run
from faultslip.cli.printing import _emit
from faultslip.errors import InputError
from faultslip.friction.contact import (contact_modulus, elastic_contact_hardness, greenwood_williamson,
                                        hirst_hollander_index, plasticity_index)
from faultslip.io.outputs import FIGURE_SUFFIXES
from faultslip.lab.surfaces import (approach_for_load, flat_like, gaussian_surface, read_surface, report, statistics,
                                    truncation_contact)
from faultslip.plots.surfaces import surface_figure
from faultslip.units import to_si


def cmd_surface(args) -> int:
    plot = _outputs(args, {"plot": ("--plot", FIGURE_SUFFIXES)}, [args.surface] if args.surface else [])["plot"]
    if (args.surface is None) == (args.synthetic is None):
        raise InputError("give a surface file, or --synthetic RMS CORRELATION_LENGTH (e.g. '2 um' '20 um')")
    if args.surface:
        surface = read_surface(args.surface)
    else:
        rms, length = (to_si(text, "length", "--synthetic") for text in args.synthetic)
        surface = gaussian_surface(rms, length, size=args.size, profile=args.profile, seed=args.seed)
    surface = surface.levelled()
    stats = statistics(surface)
    plasticity = {}
    if args.modulus:
        modulus = contact_modulus(to_si(args.modulus, "pressure", "--modulus"), _number(args.poisson, "--poisson"))
        plasticity["contact_modulus"] = (modulus, "E' = E / (2 (1 - nu^2)), like surfaces (seed 000 eq. 37), Pa")
        plasticity["elastic_contact_hardness"] = (elastic_contact_hardness(modulus, stats["summit_sigma"],
                                                                           stats["summit_radius"]),
                                                  "H' = 0.25 E' sqrt(s/R) (eq. 38), Pa")
        if args.hardness:
            hardness = to_si(args.hardness, "pressure", "--hardness")
            plasticity["plasticity_index"] = (plasticity_index(modulus, hardness, stats["summit_sigma"],
                                                               stats["summit_radius"]),
                                                "plasticity index from the summits, psi = (E'/H) sqrt(s/R) (Greenwood "
                                                "& Williamson; eq. 36): s, R the summits' height spread and radius")
            plasticity["hirst_hollander_index"] = (hirst_hollander_index(modulus, hardness, stats["rms"],
                                                                         stats["correlation_length"]),
                                                   "plasticity index from the profile, psi = 0.6 (E'/H)(sigma/beta*) "
                                                   "(Hirst & Hollander; eq. 15): sigma, beta* the heights' rms and "
                                                   "correlation length; the two differ as summit and profile "
                                                   "statistics do, both > 1 means plastic contact")
    counter = flat_like(surface) if args.against == "flat" else None
    if args.against not in ("flat", "inverted"):
        raise InputError(f"--against must be flat or inverted, got {args.against!r}")
    flow = to_si(args.flow_pressure, "pressure", "--flow-pressure") if args.flow_pressure else None
    approaches = np.linspace(0.0, 2.0 * stats["rms"], 9)
    contact = truncation_contact(surface, approaches, counter, flow)
    at_load = None
    if args.load:
        if flow is None:
            raise InputError("--load needs --flow-pressure (all contacts plastic: L = p_c A, seed 000 eq. 23)")
        at_load = approach_for_load(surface, to_si(args.load, "force", "--load"), flow, counter)
    gw = None
    if args.modulus and surface.is_map and np.isfinite(stats["summit_radius"]):
        gw = greenwood_williamson(np.linspace(0.0, 2.0, 5) * stats["summit_sigma"], stats["summit_density"],
                                  stats["summit_radius"], stats["summit_sigma"], plasticity["contact_modulus"][0],
                                  contact["nominal_area"])
    result = report(surface, stats, contact, gw, plasticity, at_load)
    _save_run(result, {"plot": plot}, args, None, lambda: surface_figure(surface, stats, contact),
              drawing="surface, autocorrelation, height density and contact")
    return _emit(result, args.json)
