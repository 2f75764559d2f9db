"""Scenarios: a model's policies run against the context given over virtual time, and the
adaptation expected of them checked (``acordcs-gen test``; docs/testing.md). The format and its
checks against the model (:mod:`.scenario_file`, read by :mod:`.yaml_reading`, names from
:mod:`.model_names`), the run on the runtime's own policy sets (:mod:`.virtual_run`), the
judgement of expectations (:mod:`.scenario_run`)."""
