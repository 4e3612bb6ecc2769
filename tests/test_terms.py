"""``terms`` lists exactly the physics a scene builds, per formulation: the fluid terms
(drag on the line's velocity relative to the water, added mass) wherever a line is in water
with such coefficients, not only where a current flows; none in air."""
import pytest

import symcable as sc
from symcable.scene import scene_to_dict


@pytest.mark.parametrize("name, expected", [
    ("sphere", {"elastic", "weight", "drag", "added mass", "point drag"}),
    ("towed_body", {"elastic", "weight", "drag", "added mass", "body added mass", "body drag"}),
    ("seed000_rod", {"elastic", "weight", "bending", "torsion", "drag"}),
    ("seed000_hybrid", {"elastic", "weight", "bending", "torsion", "drag"}),
])
def test_mechanism_terms_name_the_fluid_loads(name, expected):
    """The still-water sphere, the tow and the rods build Morison drag on the line (and
    added mass where Ca > 0: the rods' line types have Ca = 0)."""
    terms = set(sc.build_mechanism(name).terms)
    assert expected <= terms, terms
    if name.startswith("seed000"):
        assert "added mass" not in terms


def test_no_fluid_terms_in_air():
    d = scene_to_dict(sc.load_scene("sphere"))
    d["environment"]["water_density"] = 0.0
    terms = set(sc.build_mechanism(d).terms)
    assert not {"drag", "added mass"} & terms, terms


def test_planar_dynamics_terms():
    """The planar line's linearised dynamics list inertia, drag and added mass; its statics
    (no velocity) only the current's drag."""
    model = sc.build_dynamic_model("seed001")
    assert {"inertia", "drag", "added mass"} <= set(model.info["terms"])
    assert "added mass" not in sc.build_model(sc.load_scene("seed001")).terms
