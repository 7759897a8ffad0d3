"""Apps served to a browser (faultslip classroom)."""
