"""Component providers (paper, section 3): a repository of component descriptions searched with XPath,
whose factories live on HTTP servers and are installed into containers at run time."""

from acordcs.runtime.repository.catalog import ComponentRepository
from acordcs.runtime.repository.description import (
    ComponentDescription,
    PortDescription,
    parse_description,
)
from acordcs.runtime.repository.errors import RepositoryError
from acordcs.runtime.repository.installer import FactoryHost, FactoryInstaller, InstalledFactory
from acordcs.runtime.repository.server import FactoryServer

__all__ = [
    "ComponentDescription",
    "ComponentRepository",
    "FactoryHost",
    "FactoryInstaller",
    "FactoryServer",
    "InstalledFactory",
    "PortDescription",
    "RepositoryError",
    "parse_description",
]
