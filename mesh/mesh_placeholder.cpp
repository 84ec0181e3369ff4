// Replaced by the tessellation sources.
namespace icobrdf { int mesh_library_anchor() { return 0; } }
