"""Small mechanisms that test the solvers: pendulums, oscillators, a forced string."""
