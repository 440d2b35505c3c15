"""The checks of `study.py check` and `study.py check-docs` (check_study.py): a run's outputs
(run_outputs), and the findings each doc cites, one module per doc (or section of one), each against
the committed CSVs in docs/study/. Each finding's check is named; the docs cite it ("guarded by
`study.py check-docs`: name"). A check returns the line it prints, or raises common.Finding with what
the CSV shows instead."""
