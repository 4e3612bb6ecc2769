"""The per-Mechanism caches free a Mechanism once nothing else holds it, even when a cached
value refers back to it (symcable.mechanism.attached): a weak-keyed dictionary kept every
Mechanism whose step Functions closed over it, and a process solving many scenes in turn
grew by about 80 MB a scene until the system killed it."""
import functools
import gc
import weakref

import symcable as sc
from symcable.api.cable3d_static import cable3d_mechanism
from symcable.mechanism.attached import Attached
from symcable.mechanism.functions import functions
from symcable.scene import load_scene
from symcable.solvers.stepcache import STEP_CACHE


class _Owner:
    pass


def test_a_value_referring_to_its_owner_is_freed_with_it():
    cache = Attached("test")
    owner = _Owner()
    cache.setdefault(owner, functools.partial(dict, back=owner))
    ref = weakref.ref(owner)
    assert len(cache) == 1
    del owner
    gc.collect()
    assert ref() is None and len(cache) == 0


def test_step_cache_entries_go_with_their_mechanism():
    """A Mechanism with a step-cache entry that holds it, and its Functions, is collected
    once the caller and the scene caches let go of it (the scene caches: by content, and the
    templates of each structure, :mod:`symcable.models.structure`)."""
    mech = cable3d_mechanism(load_scene(sc.demo_scene_path("sphere")))
    STEP_CACHE.get(mech, ("test_back_reference",), functools.partial(dict, held=mech))
    functions(mech)
    ref = weakref.ref(mech)
    n = len(STEP_CACHE)
    del mech
    from symcable.api import cable3d_static
    from symcable.models import structure
    cable3d_static._CACHE.clear()
    structure.TEMPLATES.clear()
    gc.collect()
    assert ref() is None
    assert len(STEP_CACHE) < n
