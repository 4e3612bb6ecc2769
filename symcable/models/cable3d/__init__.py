"""The 3D cable of Sun, Zhu & LaRosa: two-node elements with node positions as unknowns
(:mod:`.line`), and its element form for the solvers (:mod:`.elements`)."""
