"""The planar cable of seed 001: its statics in angle and strain (:mod:`.model`, as a
Mechanism by :mod:`.static`) and its dynamics linearised about the static state
(:mod:`.dynamics`, as a Mechanism by :mod:`.mechanism`)."""
