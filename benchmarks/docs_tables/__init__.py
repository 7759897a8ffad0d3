"""The docs tables readme.py writes, one module per topic: each renders tables from benchmarks/results/ and
lists them in its ``TABLES``, by the marker name the pages carry (``<!-- table:NAME -->``)."""
