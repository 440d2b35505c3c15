"""The study's Python: what reads cloth_study's CSVs (and NVIDIA Newton's harness, which writes rows
beside them), one module per command of tools/study/study.py, each with a main(argv).

    check_study          study.py check, check-docs: a run's outputs; the findings the docs state
    plot_study           study.py plot-study: error against run time, stability maps
    plot_front           study.py plot-front: the front's figure
    front_checks         study.py front-checks: front.csv's columns recomputed
    front_table          study.py front-table: the front's Markdown tables
    merge_shards         study.py merge-shards: shards joined into a serial run's CSVs
    compare_runs         study.py compare-runs: two runs agree but for the timings
    nvidia_newton_study  study.py nvidia-newton: NVIDIA Newton's solvers (a venv)
    checks/              the checks behind check_study, one module per doc
    nvidia_newton/       the harness behind nvidia_newton_study
"""
