"""Reading UML exports: a model file read safely (:mod:`.source`), the neutral UML view
(:mod:`.uml`), and the readers of the XMI dialects real tools write (:mod:`.readers`)."""
