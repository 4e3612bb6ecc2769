"""The planar cable of Boral, Hickey & Basu: its statics in angle and strain (:mod:`.model`,
as a Mechanism by :mod:`.static`) and its dynamics linearised about the static state
(:mod:`.dynamics`, as a Mechanism by :mod:`.mechanism`)."""
