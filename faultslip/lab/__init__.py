"""Laboratory records: motion records, stick-slip event analysis and free-decay identification.
"""
