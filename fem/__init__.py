"""2D piezoelastic finite-element model of the stator plate (scikit-fem)."""
