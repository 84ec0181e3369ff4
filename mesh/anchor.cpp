// Mesh library anchor (the tessellation sources join this library).
namespace icobrdf::mesh_detail { int anchor() { return 0; } }
