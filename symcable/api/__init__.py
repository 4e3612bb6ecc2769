"""The analyses of a scene, from scene to result: the only package that imports both the
formulations (:mod:`symcable.models`) and the solvers (:mod:`symcable.solvers`)."""
