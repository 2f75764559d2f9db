"""The ACORD-CS reading of a UML view (:mod:`.architecture`), the questions asked of it
(:mod:`.queries`), the checks (:mod:`.checks`), the rules on generated names
(:mod:`.generated_names`), reading and checking a file in one call (:mod:`.reading`), and the model
as pyecore instances of the metamodel (:mod:`.ecore_builder`)."""
