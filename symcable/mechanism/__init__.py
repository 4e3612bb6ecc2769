"""The Mechanism, the one interface every formulation produces (:mod:`.mechanism`), its
assembly from parts (:mod:`.assembly`) and element kernels (:mod:`.element_form`), the
CasADi Functions derived from it once per structure (:mod:`.functions`,
:mod:`.static_functions`), and generated C with its build cache (:mod:`.codegen`)."""
