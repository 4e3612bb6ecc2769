"""What the analyses return: plain result types with ``summary()``, ``plot()``, ``save()``
and ``load()`` (static solutions, trajectories, periodic solutions, modes, linearisations,
offset sweeps, sweep tables)."""
