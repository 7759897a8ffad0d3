"""The public API, by topic, in one table: what ``faultslip.io``, ``friction``, ``lab``, ``models``, ``hazard`` and
``plots`` export, and where each name lives.

``import faultslip`` gives the command line's five verbs (``run``, ``simulate``, ``sweep``, ``fit``, ``map``), the
:class:`~faultslip.contract.result.Result` they return, the errors and the unit registry; everything else is one
topic down, as pvlib's ``pvlib.iotools`` and ``pvlib.irradiance`` are: ``faultslip.lab.read_look``,
``faultslip.hazard.rupture_set``. One verb per idea: ``read_*`` reads a file and ``parse_*`` the same from text (as pvlib's iotools), ``analyze_*`` measures a record,
``simulate_*`` integrates in time, ``*_figure`` draws.

Each topic's names are loaded on first use (PEP 562), so ``import faultslip`` and the command line start fast.
The flat names of earlier releases (``faultslip.read_look``, ``faultslip.load_scene``) still resolve, with a
FutureWarning naming the new place, for one release (:data:`MOVED`).
"""

from __future__ import annotations

import importlib
import warnings

#: topic -> public name -> "module:attribute" (module relative to faultslip). A topic is a subpackage of faultslip
#: (``hazard`` is a facade only); a name is exported from its own layer or one below it.
TOPICS = {
    "io": {
        "read_catalog": "io.catalogs:read_catalog", "write_quakeml": "io.catalogs:write_quakeml",
        "read_stream": "io.waveforms:read_stream", "write_stream": "io.waveforms:write_stream",
        "build_stream": "io.waveforms:build_stream", "read_seas": "io.seas:read_seas",
        "read_bundle": "io.bundle:read_bundle", "write_bundle": "io.bundle:write_bundle",
        "config_path": "io.resources:config_path", "bundled_examples": "io.resources:bundled_examples",
    },
    "friction": {
        **{name: f"friction.laws:{name}" for name in (
            "CallableKinetic", "ConstantKinetic", "ConstantStatic", "LinearKinetic", "PolynomialKinetic", "RateLaw",
            "TimeOfStickLaw", "static_friction")},
        **{name: f"friction.materials:{name}" for name in (
            "get_lithology", "get_preset", "lithologies", "presets", "fits", "save_fit")},
        "fit_rate_law": "friction.fitting:fit_rate_law", "read_friction_data": "friction.fitting:read_friction_data",
    },
    "lab": {
        "fit": "lab.fit_workflow:fit", "fit_record": "lab.fit_workflow:fit_record",
        "read_step_record": "lab.rate_state_fit:read_step_record", "step_record": "lab.rate_state_fit:step_record",
        "fit_velocity_steps": "lab.rate_state_fit:fit_velocity_steps", "fit_joint": "lab.rate_state_fit:fit_joint",
        "read_raw_record": "lab.raw_records:read_raw_record", "raw_record": "lab.raw_records:raw_record",
        "read_rig_record": "lab.raw_records:read_rig_record", "prepare_record": "lab.raw_records:prepare_record",
        "detect_steps": "lab.raw_records:detect_steps", "fit_each_step": "lab.raw_records:fit_each_step",
        "synthetic_raw_record": "lab.raw_records:synthetic_raw_record",
        "sample_posterior": "lab.posterior:sample_posterior", "parse_prior": "lab.posterior:parse_prior",
        "Prior": "lab.posterior:Prior",
        "read_record": "lab.records:read_record", "analyze_record": "lab.records:analyze_record",
        "free_decay": "lab.records:free_decay", "free_decay_from_record": "lab.records:free_decay_from_record",
        "read_accelerometer": "lab.classroom:read_accelerometer", "analyze_accelerometer": "lab.classroom:analyse",
        "read_surface": "lab.surfaces:read_surface", "analyze_surface": "lab.surfaces:analyze_surface",
        "gaussian_surface": "lab.surfaces:gaussian_surface", "surface_statistics": "lab.surfaces:statistics",
        "truncation_contact": "lab.surfaces:truncation_contact", "approach_for_load": "lab.surfaces:approach_for_load",
        "read_look": "lab.look_files:read_look", "parse_look": "lab.look_files:parse_look",
        "parse_look_ascii": "lab.look_files:parse_look_ascii", "run_r_file": "lab.look_reduction:run_r_file",
        "run_commands": "lab.look_reduction:run_commands",
        "select_law": "lab.law_selection:select_law",
        "lag_one_autocorrelation": "lab.law_selection:lag_one_autocorrelation",
        "hold_healing": "lab.healing:healing", "steady_state_dependence": "lab.healing:steady_state_dependence",
    },
    "models": {
        # the contract
        "Result": "models:Result", "families": "models:families", "family_of": "models:family_of",
        "check_family": "models.checks:check_family", "estimate": "models:estimate",
        "methods": "models:methods",
        # the seed's spring slider and its fault
        "read_slider_scene": "fault.scene:read_slider_scene", "Fault": "fault.scaling:Fault",
        "SliderSystem": "dynamics.spring_slider.slider:SliderSystem", "solve": "dynamics.methods:solve",
        "exact_cycle": "dynamics.spring_slider.exact_cycle:exact_cycle",
        "critical": "dynamics.spring_slider.critical:critical",
        "closed_form_cycle": "dynamics.spring_slider.closed_form:closed_form_cycle",
        "loading_rate": "dynamics.spring_slider.closed_form:loading_rate",
        "rate_law_amplitude": "dynamics.spring_slider.closed_form:rate_law_amplitude",
        "slip_amplitude": "dynamics.spring_slider.closed_form:slip_amplitude",
        "simulate_slider": "dynamics.spring_slider.simulate:simulate",
        "scene_cycle": "models.spring_slider.family:cycle",
        # the rate-and-state slider and the ladder's one-slider rung
        "read_rate_state_scene": "models.rate_state_slider.scene:read_rate_state_scene",
        "simulate_rate_state": "dynamics.rate_state.slider:simulate_rate_state",
        "fault_cycles": "dynamics.rate_state.slider:fault_cycles",
        "rate_state_stability": "models.rate_state_slider.family:stability",
        "velocity_step": "models.rate_state_slider.family:velocity_step",
        "earthquake_cycles": "models.rate_state_slider.cycles:earthquake_cycles",
        "earthquake_cycles_beside_seed_law": "models.rate_state_slider.family:earthquake_cycles",
        "model_error": "models.rate_state_slider.model_error:model_error_result",
        "declared_model_error": "models.rate_state_slider.model_error:declared_model_error",
        "read_one_slider_calibration": "models.rate_state_slider.one_slider:load_calibration",
        "model_error_figure": "models.rate_state_slider.figures:model_error_figure",
        # quasi-harmonic vibration (seed 002)
        "read_vibration_scene": "models.vibration.scene:read_vibration_scene",
        "QuasiHarmonic": "dynamics.vibration:QuasiHarmonic",
        "amplitude_against_speed": "dynamics.vibration:amplitude_against_speed",
        "amplitude_study": "models.vibration.family:amplitude_study",
        "amplitude_speed_figure": "models.vibration.figures:amplitude_speed_figure",
        # nanoscale (seed 001)
        "NanoscaleModel": "models.nanoscale.dynamics:NanoscaleModel",
        "nanoscale_swing": "models.nanoscale.family:swing",
        "nanoscale_figure": "models.nanoscale.figures:nanoscale_figure",
        # asperities (seed 004)
        "AsperityModel": "models.asperity.dynamics:AsperityModel",
        "simulate_asperity": "models.asperity.dynamics:simulate",
        "analyze_asperity": "models.asperity.dynamics:analyse",
        "asperity_speed_study": "models.asperity.family:speed_study",
        "asperity_figure": "models.asperity.figures:response_figure",
        # rough surfaces (seed 000)
        "read_rough_scene": "models.rough_surface.scene:read_rough_scene",
        "rough_surface_slider": "models.rough_surface.scene:rough_surface_slider",
        "separation_history": "models.rough_surface.scene:separation_history",
        # the 2-D fault
        "read_fault_2d_scene": "models.fault_2d.scene:read_fault_2d_scene",
        "simulate_fault": "models.fault_2d.family:simulate_fault",
        "cumulative_slip_figure": "models.fault_2d.figures:cumulative_slip_figure",
        "slip_rate_figure": "models.fault_2d.figures:slip_rate_figure",
        # the spring-block chain
        "read_chain_scene": "models.spring_chain.scene:read_chain_scene",
        "parse_chain_scene": "models.spring_chain.scene:parse_chain_scene",
        "Chain": "models.spring_chain.dynamics:Chain", "simulate_chain": "models.spring_chain.dynamics:simulate_chain",
        "chain_statistics": "models.spring_chain.family:statistics",
        "chain_figure": "models.spring_chain.figures:chain_figure",
    },
    "hazard": {
        "map": "studies.maps:regional_map", "read_map": "studies.maps:read_map", "run_map": "studies.maps:run_map",
        "map_estimate": "studies.maps:map_size_estimate", "sweep_estimate": "studies.streaming:sweep_estimate",
        "segment_map": "studies.maps:segment_map", "observed_table": "studies.maps:observed_table",
        "rupture_set": "studies.rupture_sets:rupture_set",
        "hazard_sources": "studies.hazard:hazard_sources", "source_models": "studies.hazard:source_models",
        "write_hazard_model": "studies.hazard:write_hazard_model", "write_engine_job": "studies.hazard:write_engine_job",
        "displacement_hazard": "studies.displacement_hazard:displacement_hazard",
        "displacement_hazard_curve": "fault.displacement:displacement_hazard_curve",
        "moment_magnitude": "fault.scaling:moment_magnitude", "seismic_moment": "fault.scaling:seismic_moment",
        "conditional_probability": "fault.recurrence:conditional_probability", "fit_renewal": "fault.recurrence:fit",
        "youngs_coppersmith_1985": "fault.mfd:youngs_coppersmith_1985",
        "truncated_gutenberg_richter": "fault.mfd:truncated_gutenberg_richter", "single_bin": "fault.mfd:single_bin",
        "b_value": "fault.gutenberg_richter:b_value", "predictability": "fault.predictability:predictability",
        "catalog_predictability": "evaluation.predictability:catalog_predictability",
        "compare_catalog": "evaluation.catalogs:compare", "compare_empirical": "fault.empirical:compare",
        **{name: f"fault.empirical:{name}" for name in (
            "magnitude_from_length", "magnitude_from_area", "average_displacement", "maximum_displacement",
            "rupture_length", "rupture_area", "rupture_width", "magnitude_from_width", "magnitude_from_displacement",
            "wells_coppersmith_1994", "leonard_magnitude_from_area", "leonard_magnitude_from_length", "leonard_width",
            "leonard_length_from_magnitude", "leonard_area_from_magnitude", "leonard_range")},
    },
    "plots": {
        **{name: f"plots.figures:{name}" for name in (
            "sawtooth_figure", "phase_plane_figure", "rate_law_figure", "classroom_figure")},
        "catalog_figure": "plots.catalogs:catalog_figure", "surface_figure": "plots.surfaces:surface_figure",
        "corner_figure": "plots.posterior:corner_figure", "record_fit_figure": "plots.posterior:record_fit_figure",
        "predictability_figure": "plots.predictability:predictability_figure",
        "fault_system_figure": "plots.fault_maps:fault_system_figure",
        "displacement_hazard_figure": "plots.displacement:displacement_hazard_figure",
        "map_figure": "studies.maps:map_figure", "fit_figure": "friction.fitting:fit_figure",
    },
}

#: The top level: the command line's five verbs, the Result they return, the errors and the units.
TOP = {
    "run": "models:run", "simulate": "models:simulate", "sweep": "studies.grid:sweep", "fit": "lab.fit_workflow:fit",
    "map": "studies.maps:regional_map", "Result": "contract.result:Result",
    **{name: f"errors:{name}" for name in ("FaultslipError", "InputError", "MethodError", "OutOfDomainWarning",
                                           "SolverError")},
    "units": "units:units", "JULIAN_YEAR": "units:JULIAN_YEAR",
}

#: Flat top-level names of earlier releases that are not the new names of the same object -> "topic.name".
_RENAMED = {"load_scene": "models.read_slider_scene", "load_rate_state_scene": "models.read_rate_state_scene",
            "load_vibration_scene": "models.read_vibration_scene", "load_rough_scene": "models.read_rough_scene",
            "load_fault_2d_scene": "models.read_fault_2d_scene", "load_chain_scene": "models.read_chain_scene",
            "load_calibration": "models.read_one_slider_calibration",
            "load_map": "hazard.read_map", "load_record": "lab.read_rig_record", "analyse_accelerometer": "lab.analyze_accelerometer",
            "analyse_surface": "lab.analyze_surface", "analyse_asperity": "models.analyze_asperity",
            "healing": "lab.hold_healing", "simulate_scene": "faultslip.simulate", "run_scene": "faultslip.run"}
#: What each old name resolved to, where the new name is another object or none (module:attribute).
_OLD_TARGETS = {"simulate_scene": "models:simulate", "run_scene": "fault.scene:run_scene"}


def _moved() -> dict:
    """old flat name -> (its new place, as a user writes it; the module:attribute it resolves to)."""
    moved = {}
    for topic, names in TOPICS.items():
        for name, where in names.items():
            if name not in TOP:
                moved.setdefault(name, (f"faultslip.{topic}.{name}", where))
    for old, new in _RENAMED.items():
        topic, _, name = new.partition(".")
        where = _OLD_TARGETS.get(old) or (TOPICS[topic][name] if topic in TOPICS else TOP[name])
        moved[old] = (new if new.startswith("faultslip.") else f"faultslip.{new}", where)
    return moved


#: old flat name -> (new place, module:attribute), for one release (a FutureWarning says where each went).
MOVED = _moved()


def resolve(where: str):
    """The object at ``"module:attribute"`` (module relative to faultslip), imported on first use."""
    module, _, attribute = where.partition(":")
    return getattr(importlib.import_module(f"faultslip.{module}" if module else "faultslip"), attribute)


def exports(package: str, table: dict, defined=()):
    """A topic package's ``__getattr__``, ``__dir__`` and ``__all__`` over ``table`` (name -> module:attribute),
    beside the names the package defines itself (``defined``)."""
    names = sorted(set(table) | set(defined))

    def __getattr__(name):  # noqa: N807 - PEP 562
        if name in table:
            value = resolve(table[name])
            setattr(importlib.import_module(package), name, value)
            return value
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def __dir__():  # noqa: N807 - PEP 562
        return sorted(set(vars(importlib.import_module(package))) | set(names))

    return __getattr__, __dir__, names


def moved(name: str):
    """An old flat name's object, with a FutureWarning saying where it lives now; None if ``name`` is not one."""
    if name not in MOVED:
        return None
    new, where = MOVED[name]
    warnings.warn(f"faultslip.{name} is {new} now; the top-level name goes in the next release",
                  FutureWarning, stacklevel=3)
    return resolve(where)


def public_names() -> dict:
    """Every public name as a user writes it (``faultslip.run``, ``faultslip.lab.read_look``) -> module:attribute."""
    table = {f"faultslip.{name}": where for name, where in TOP.items()}
    for topic, names in TOPICS.items():
        table.update({f"faultslip.{topic}.{name}": where for name, where in names.items()})
    return table
