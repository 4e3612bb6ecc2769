"""Solvers, generic over every formulation: they see a Model's functions, never a cable."""
