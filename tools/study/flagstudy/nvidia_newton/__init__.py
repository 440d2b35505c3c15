"""NVIDIA Newton's cloth solvers on the study's flags and pole motion (`study.py nvidia-newton`,
nvidia_newton_study.py): the input (case, read and checked by load), the air of the extreme cases
(extreme), the Newton models (models) and solver settings (solvers), one run of a configuration
(run), its metrics (metrics) and the CSV rows (output)."""
