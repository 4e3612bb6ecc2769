"""Figures of results (the only package that imports matplotlib): profiles and series of
the planar line (:mod:`.profiles`), 3D views (:mod:`.view3d`, :mod:`.line3d`), bodies,
systems of lines and tows."""
