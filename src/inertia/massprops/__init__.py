"""Mass properties: the value type, primitives, meshes, assemblies, transforms, canonical form, validity."""
