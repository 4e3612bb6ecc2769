"""Physics shared by the formulations, written once: segments and the tension-only law,
the catenary starts, the cable element, drag laws, seabed contact and friction, the
relaxation starts and the terms a scene needs."""
