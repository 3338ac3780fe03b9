"""tb_exudyn.results."""
