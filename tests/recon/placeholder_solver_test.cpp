// Replaced by the solver tests.
