"""The 6-DOF rigid body: a part of a scene of lines, points and bodies."""
