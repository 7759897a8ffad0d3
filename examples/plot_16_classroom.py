"""
The classroom experiment: a phone pulled through a rubber band
==============================================================

A phyphox accelerometer export (here synthetic, configs/example_phyphox.csv): the slips stand out of
the sensor noise, and each one's acceleration at break-away gives mu_s - mu_k.
"""
from faultslip.lab import analyze_accelerometer, read_accelerometer
from faultslip.plots import classroom_figure
from faultslip.io import config_path

analysis = analyze_accelerometer(read_accelerometer(config_path("example_phyphox.csv")))
print(analysis.report("phone on a table").to_text())
classroom_figure(analysis)
