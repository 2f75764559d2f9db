"""The repository's own tools, not installed with the package: the BOUML-style XMI writer that
writes the samples and the synthetic benchmark model (:mod:`tools.bouml_writer`), and the scripts
that regenerate files derived from the metamodel and the rule grammar."""
