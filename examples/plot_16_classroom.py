"""
The classroom experiment: a phone pulled through a rubber band
==============================================================

A phyphox accelerometer export (here synthetic, configs/example_phyphox.csv): the slips stand out of
the sensor noise, and each one's acceleration at break-away gives mu_s - mu_k.
"""
from faultslip.io.resources import config_path
from faultslip.lab.classroom import analyse, read_accelerometer
from faultslip.plots.figures import classroom_figure

analysis = analyse(read_accelerometer(config_path("example_phyphox.csv")))
print(analysis.report("phone on a table").to_text())
classroom_figure(analysis)
