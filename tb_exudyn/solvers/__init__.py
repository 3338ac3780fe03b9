"""tb_exudyn.solvers."""
