"""faultslip: laboratory rock-friction stick-slip scaled to earthquake slip and recurrence.

The physics follows seed 003 (Friction-induced oscillations in rock systems):
a spring-slider whose static friction rises as the loading rate falls
(eq. 2-18), whose stick-slip amplitude follows eq. 2-19, and which, scaled to
a strike-slip fault (§5-2), predicts slip per earthquake and recurrence.

Internally every quantity is SI; the year is the Julian year (365.25 d).
"""

__version__ = "0.1.0"

# The public API, loaded on first use (PEP 562): "import faultslip" and the command line start fast,
# and a Ctrl-C during start-up reaches the CLI's handler instead of an import.
_EXPORTS = {
    "dynamics.spring_slider.closed_form": ("closed_form_cycle", "loading_rate", "rate_law_amplitude", "slip_amplitude"),
    "errors": ("FaultslipError", "InputError", "MethodError", "OutOfDomainWarning", "SolverError"),
    "fault.scaling": ("Fault", "moment_magnitude", "seismic_moment"),
    "friction.laws": ("CallableKinetic", "ConstantKinetic", "ConstantStatic", "LinearKinetic", "PolynomialKinetic",
                      "RateLaw", "TimeOfStickLaw", "static_friction"),
    "friction.materials": ("get_lithology", "get_preset", "lithologies", "presets", "fits", "save_fit"),
    "friction.fitting": ("fit_rate_law", "read_friction_data"),
    "fault.scene": ("load_scene", "run_scene"),
    "dynamics.spring_slider.slider": ("SliderSystem",),
    "dynamics.methods": ("solve",),
    "dynamics.spring_slider.exact_cycle": ("exact_cycle",),
    "dynamics.spring_slider.critical": ("critical",),
    "studies.grid": ("sweep",),
    "units": ("JULIAN_YEAR", "units"),
    "models": ("run", "simulate", "Result", "family_of", "families"),
    # every capability of the command line, by topic (docs/api.rst)
    "io.resources": ("config_path",),
    "io.catalogs": ("read_catalog", "write_quakeml"),
    "io.waveforms": ("build_stream", "read_stream", "write_stream"),
    "studies.maps": ("load_map", "segment_map", "run_map", "map_figure", "observed_table"),
    "fault.recurrence": ("conditional_probability",),
    "fault.empirical": ("magnitude_from_length", "magnitude_from_area", "average_displacement",
                        "maximum_displacement", "rupture_length", "rupture_area", "rupture_width",
                        "magnitude_from_width", "magnitude_from_displacement", "wells_coppersmith_1994",
                        "leonard_magnitude_from_area", "leonard_magnitude_from_length", "leonard_width",
                        "leonard_length_from_magnitude", "leonard_area_from_magnitude", "leonard_range"),
    "fault.mfd": ("youngs_coppersmith_1985", "truncated_gutenberg_richter", "single_bin"),
    "studies.hazard": ("hazard_sources", "source_models", "write_hazard_model", "write_engine_job"),
    "fault.rate_state_scene": ("load_rate_state_scene",),
    "dynamics.rate_state.slider": ("simulate_rate_state", "fault_cycles"),
    "lab.rate_state_fit": ("read_step_record", "step_record", "fit_velocity_steps", "fit_joint"),
    "lab.raw_records": ("read_raw_record", "raw_record", "prepare_record", "detect_steps", "fit_each_step",
                        "synthetic_raw_record", "load_record"),
    "lab.posterior": ("sample_posterior", "parse_prior", "Prior"),
    "lab.fit_workflow": ("fit_record",),
    "plots.posterior": ("corner_figure", "record_fit_figure"),
    "lab.records": ("read_record", "analyze_record", "free_decay", "free_decay_from_record"),
    "lab.classroom": ("read_accelerometer",),
    "lab.surfaces": ("gaussian_surface", "read_surface", "truncation_contact", "approach_for_load"),
    "models.vibration.scene": ("load_vibration_scene",),
    "models.rough_surface.scene": ("load_rough_scene", "rough_surface_slider", "separation_history"),
    "dynamics.vibration": ("QuasiHarmonic", "amplitude_against_speed"),
    "models.nanoscale.dynamics": ("NanoscaleModel",),
    "models.asperity.dynamics": ("AsperityModel",),
    "plots.figures": ("sawtooth_figure", "phase_plane_figure", "rate_law_figure", "classroom_figure"),
    "plots.catalogs": ("catalog_figure",),
    "plots.surfaces": ("surface_figure",),
    "models.nanoscale.figures": ("nanoscale_figure",),
    "models.vibration.figures": ("amplitude_speed_figure",),
    "models.fault_2d.scene": ("load_fault_2d_scene",),
    "models.fault_2d.family": ("simulate_fault",),
    "models.rate_state_slider.model_error": ("declared_model_error",),
    "fault.one_slider": ("load_calibration",),
    "models.fault_2d.figures": ("cumulative_slip_figure", "slip_rate_figure"),
    "models.rate_state_slider.figures": ("model_error_figure",),
    "io.seas": ("read_seas",),
    "fault.predictability": ("predictability",),
    "evaluation.predictability": ("catalog_predictability",),
    "lab.look_files": ("read_look", "parse_look", "parse_look_ascii"),
    "lab.look_reduction": ("run_r_file", "run_commands"),
    "plots.predictability": ("predictability_figure",),
    "fault.gutenberg_richter": ("b_value",),
    "models.spring_chain.scene": ("load_chain_scene", "parse_chain_scene"),
    "models.spring_chain.dynamics": ("Chain", "simulate_chain"),
    "models.spring_chain.figures": ("chain_figure",),
    "studies.rupture_sets": ("rupture_set",),
    "studies.displacement_hazard": ("displacement_hazard",),
    "fault.displacement": ("displacement_hazard_curve",),
    "plots.fault_maps": ("fault_system_figure",),
    "plots.displacement": ("displacement_hazard_figure",),
    "lab.law_selection": ("select_law", "lag_one_autocorrelation"),
    "lab.healing": ("healing", "steady_state_dependence"),
    "io.bundle": ("write_bundle", "read_bundle"),
}
#: Public names whose module's own name would be ambiguous at the top level: name -> (module, attribute).
_ALIASES = {
    "compare_catalog": ("evaluation.catalogs", "compare"),
    "fit_renewal": ("fault.recurrence", "fit"),
    "compare_empirical": ("fault.empirical", "compare"),
    "analyse_accelerometer": ("lab.classroom", "analyse"),
    "surface_statistics": ("lab.surfaces", "statistics"),
    "analyse_asperity": ("models.asperity.dynamics", "analyse"),
    "simulate_asperity": ("models.asperity.dynamics", "simulate"),
    "asperity_figure": ("models.asperity.figures", "response_figure"),
    "fit_figure": ("friction.fitting", "fit_figure"),
    # the five top-level verbs of the command line: run, simulate and sweep above, and these
    "fit": ("lab.fit_workflow", "fit"),
    "map": ("studies.maps", "regional_map"),
    "simulate_scene": ("models", "simulate"),
    "simulate_slider": ("dynamics.spring_slider.simulate", "simulate"),
    # the computing commands' own functions (tests/test_cli_api.py: the same numbers as their --json)
    "scene_cycle": ("models.spring_slider.family", "cycle"),
    "amplitude_study": ("models.vibration.family", "amplitude_study"),
    "nanoscale_swing": ("models.nanoscale.family", "swing"),
    "asperity_speed_study": ("models.asperity.family", "speed_study"),
    "rate_state_stability": ("models.rate_state_slider.family", "stability"),
    "velocity_step": ("models.rate_state_slider.family", "velocity_step"),
    "earthquake_cycles": ("models.rate_state_slider.cycles", "earthquake_cycles"),
    "earthquake_cycles_beside_seed_law": ("models.rate_state_slider.family", "earthquake_cycles"),
    "model_error": ("models.rate_state_slider.model_error", "model_error_result"),
    "analyse_surface": ("lab.surfaces", "analyse_surface"),
    "check_family": ("models.checks", "check_family"),
    "chain_statistics": ("models.spring_chain.family", "statistics"),
}
_WHERE = {name: (module, name) for module, names in _EXPORTS.items() for name in names} | _ALIASES
__all__ = sorted(_WHERE)


def __getattr__(name):
    if name in _WHERE:
        import importlib

        module, attribute = _WHERE[name]
        value = getattr(importlib.import_module(f".{module}", __name__), attribute)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'faultslip' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))
