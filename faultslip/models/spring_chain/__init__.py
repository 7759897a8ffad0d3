"""A chain of spring-blocks (Burridge & Knopoff 1967): a fault of many blocks whose catalogue has sizes."""
