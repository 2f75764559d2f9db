"""Writing BOUML-style XMI: the elements (:mod:`.elements`), the writer (:mod:`.bouml`) and a
synthetic large model (:mod:`.synthetic`) for benchmarks and tests."""
