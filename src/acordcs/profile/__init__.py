"""The UML profile ACORDCS, derived from the metamodel's annotations (see :mod:`.declaration`)."""

from acordcs.profile.declaration import PROFILE_NAME, Stereotype, Tag, profile, stereotype

__all__ = ["PROFILE_NAME", "Stereotype", "Tag", "profile", "stereotype"]
