"""Linear algebra inside CasADi graphs, generic (no cables, no solvers): :mod:`.sparse`,
sparse solves that keep dense rows out of the factorisation; :mod:`.sxlu`, a block LU
written out in SX for generated C."""
