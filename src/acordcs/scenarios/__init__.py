"""Scenarios: a model's policies run against the context given over virtual time, and the
adaptation expected of them checked (``acordcs-gen test``; docs/testing.md). The format and its
checks against the model (:mod:`.scenario_file`, read by :mod:`.yaml_reading`, steps from CSV
files by :mod:`.csv_steps`, names from :mod:`.model_names`), the run on the runtime's own policy
sets (:mod:`.virtual_run`), the judgement of expectations (:mod:`.scenario_run`), rule coverage
(:mod:`.rule_coverage`), JUnit XML (:mod:`.junit_report`), traces and plots
(:mod:`.trace_files`)."""
