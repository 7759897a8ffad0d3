"""
A parameter sweep, plotted with xarray
======================================

``faultslip.sweep`` returns an xarray Dataset with labelled dimensions: here the 1906 fault's slip
per event over the plate rate and the elastic-zone width.
"""
import faultslip

result = faultslip.sweep("san_andreas_1906.toml", slip_rate=[f"{v} mm/yr" for v in (10, 20, 35, 50)],
                         zone_width=[f"{w} km" for w in (5, 10, 15, 20, 25, 30)])
print(result["slip_per_event"].attrs["long_name"])
years = result["recurrence_period"] / faultslip.JULIAN_YEAR
years.attrs = {"long_name": "recurrence", "units": "yr"}
years.plot.line(x="zone_width", hue="slip_rate")
