"""The toolchain: read UML (XMI), interpret it as an ACORD-CS application, validate, generate."""
