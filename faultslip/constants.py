"""Constants faultslip uses in more than one place, each defined once.

The year is the Julian year, 365.25 d: pint's ``year`` (checked when the unit registry is built,
:mod:`faultslip.units`), the astronomers' year and the one SEAS and the hazard literature count slip
rates in.
"""

#: Seconds in a day.
DAY = 86400.0
#: Seconds in a Julian year, 365.25 d.
JULIAN_YEAR = 365.25 * DAY
#: Standard gravity, m/s^2 (CGPM 1901; a weight from a mass, as a lab's load cell reads it).
STANDARD_GRAVITY = 9.80665
