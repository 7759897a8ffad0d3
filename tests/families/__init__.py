"""Model families kept for tests: each is one module, made a family by one declare() line."""
