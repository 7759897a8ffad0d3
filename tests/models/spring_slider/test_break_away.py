"""A slider whose static friction at break-away is below its kinetic friction at zero sliding speed cannot start to
slip (seed 003's stick-slip needs mu_s > mu_k(0)). Every integrator had returned something there: LSODA and Radau
events of zero slip called a growing oscillation, declared to 3.7e-7; DOP853 and RK45 one event of 32 um and then
steady sliding. Each is refused in one sentence now, by every method and both commands."""

import pytest
from conftest import assert_clean_error

from faultslip.dynamics import methods
from faultslip.dynamics.spring_slider.simulate import simulate
from faultslip.dynamics.spring_slider.slider import SliderSystem
from faultslip.errors import InputError
from faultslip.friction.laws import ConstantKinetic, LinearKinetic, PolynomialKinetic, TimeOfStickLaw

STEEL = SliderSystem.from_preset("steel_dry", platform_speed="3 m/s")  # mu_s = 0.39012 at this loading rate
ABOVE = PolynomialKinetic([0.5, -0.3 * 0.0254, 0.0, 40.0 * 0.0254 ** 3])  # mu_k(0) = 0.5, in in/s


@pytest.mark.parametrize("solver", ["DOP853", "RK45", "LSODA", "Radau"])
def test_every_integrator_refuses_a_slider_that_cannot_break_away(solver):
    with pytest.raises(InputError, match=r"break-away \(0\.39012\) is below its kinetic friction at zero sliding "
                                         r"speed, mu_k\(0\) = 0\.5"):
        simulate(STEEL.with_(kinetic_law=ABOVE), cycles=3, slip_solver=solver)


def test_the_analytic_phase_and_the_method_choice_refuse_it_too():
    linear = STEEL.with_(kinetic_law=LinearKinetic(0.45, 0.0))
    with pytest.raises(InputError, match="cannot start to slip"):
        simulate(linear, cycles=3)
    for system in (linear, STEEL.with_(kinetic_law=ABOVE)):
        with pytest.raises(InputError, match="cannot start to slip"):
            methods.solve(system)
    assessment = methods.EventDriven("LSODA").assess(linear, ("amplitude",), 1e-6, 10)
    assert not assessment.applicable and "cannot start to slip" in assessment.reason


def test_a_time_of_stick_law_is_checked_at_each_break_away():
    """Cameron's law breaks away at mu_s(stick time): from a start past the threshold, at once, at mu_lower."""
    law = TimeOfStickLaw(mu_lower=0.30, mu_upper=0.53, growth_rate=2.0)
    system = STEEL.with_(static_law=law, kinetic_law=ConstantKinetic(0.39), platform_speed="1e-3 in/s")
    with pytest.raises(InputError, match=r"break-away \(0\.3\) is below"):
        simulate(system, cycles=3, initial_displacement=0.30 * system.normal_load / system.stiffness)


def test_a_break_away_at_the_kinetic_friction_still_runs():
    """mu_s = mu_k(0) to round-off is a graze, which the slip phase handles (seed 000's slider at c = 0; Cameron's
    law from mu_lower = mu_k): not refused."""
    law = TimeOfStickLaw(mu_lower=0.39, mu_upper=0.53, growth_rate=2.0)
    system = STEEL.with_(static_law=law, kinetic_law=ConstantKinetic(0.39), platform_speed="1e-3 in/s")
    assert simulate(system, cycles=3).sizes["event"] == 3


def test_both_commands_say_it_in_one_sentence(cli, tmp_path):
    scene = tmp_path / "above.toml"
    scene.write_text('[scene]\nkind = "lab"\nname = "above"\n[lab]\npreset = "steel_dry"\nplatform_speed = "3 m/s"\n'
                     '[friction]\nkinetic = "polynomial"\npolynomial = [0.5, -0.3, 0.0, 40.0]\n'
                     'polynomial_speed_unit = "m/s"\n', encoding="utf-8")
    for command in (("run",), ("simulate", "--cycles", "3")):
        assert_clean_error(cli(command[0], scene, *command[1:]), "cannot start to slip")
