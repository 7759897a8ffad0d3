"""
The classroom experiment: a phone pulled through a rubber band
==============================================================

A phyphox accelerometer export (here synthetic, configs/example_phyphox.csv): the slips stand out of
the sensor noise, and each one's acceleration at break-away gives mu_s - mu_k.
"""
from faultslip import analyse_accelerometer, classroom_figure, config_path, read_accelerometer

analysis = analyse_accelerometer(read_accelerometer(config_path("example_phyphox.csv")))
print(analysis.report("phone on a table").to_text())
classroom_figure(analysis)
