"""The train-bridge system in plain numpy (no Exudyn): what every engine integrates.

- :mod:`.coupling`: the wheel-rail contact (kinematics, forces, Jacobians), called by the Exudyn
  user functions and read by the batched and dense engines;
- :mod:`.excitation`: the irregularity input as data (none, a sampled profile, one harmonic), the
  approach taper and the rail inputs;
- :mod:`.channels`: output channel names, units, selection and evaluation;
- :mod:`.modes`: damped modal analysis of the linearised system (mode table, labels) and the
  damping guard.
"""
