"""The Kirchhoff rod of Goyal & Perkins as a discrete elastic rod (:mod:`.rod`: bending,
torsion, frames, loads) and the hybrid rod-catenary line built on it (:mod:`.hybrid`)."""
