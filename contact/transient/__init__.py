"""Transient schemes from rest: the event-located kernel (:mod:`contact.transient.event_kernel`),
the paper's literal RK4 (:mod:`contact.transient.literal`), the ``solve_ivp`` reference
(:mod:`contact.transient.reference`) and the run window they share
(:mod:`contact.transient.window`)."""
