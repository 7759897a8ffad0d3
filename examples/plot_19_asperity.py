"""
Asperity friction: stick-slip bands and period doubling
=======================================================

Seed 004 (Bengisu & Akay 1999): a block on a moving platform, with friction from asperity
deformation and adhesion, sticks and slips only near the critical speeds v_cn = f0 lambda / n.
At v_c2 the period doubles. The quasi-static method (normal inertia neglected) is used here; the
six-state one agrees to 0.001 in the stick fraction (docs/asperity.md).
"""
from faultslip.models import AsperityModel, analyze_asperity, asperity_figure, simulate_asperity

model = AsperityModel()  # Table I case 6 at 3.6 mm/s
print("v_c1, v_c2, v_c3 (mm/s):", [f"{v * 1e3:.2f}" for v in model.critical_speeds((1, 2, 3))])
for speed in (3.6e-3, 2.7e-3, 1.8e-3):
    response = analyze_asperity(simulate_asperity(AsperityModel(platform_speed=speed), 4.0, "asperity_quasistatic"))
    print(f"v = {speed * 1e3:.1f} mm/s: stuck {response.stick_fraction:.1%} of the time, "
          f"{response.loops} loop(s) per period")
asperity_figure(simulate_asperity(AsperityModel(platform_speed=1.8e-3), 4.0, "asperity_quasistatic"))
