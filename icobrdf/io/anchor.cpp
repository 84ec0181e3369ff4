// io library anchor (the HDF5 sources join this library).
namespace icobrdf::io_detail { int anchor() { return 0; } }
