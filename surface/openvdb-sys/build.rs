//! Compiles the C++ shim against the system OpenVDB and links it.
//!
//! Debian ships no pkg-config file for OpenVDB, so the libraries are named here:
//! `openvdb`, `Imath-3_1` (its maths types) and `tbb` (its thread pool). The shim
//! takes about a minute to compile, so it is always built at -O2 (also in debug
//! profiles, where -O0 would make the level-set tools crawl) and only rebuilt when
//! the shim itself changes.

fn main() {
    println!("cargo:rerun-if-changed=shim/shim.cpp");
    println!("cargo:rerun-if-changed=build.rs");
    cc::Build::new()
        .cpp(true)
        .file("shim/shim.cpp")
        .std("c++17")
        .opt_level(2)
        .debug(false)
        .include("/usr/include/Imath")
        // OpenVDB's headers trip many warnings that are not ours.
        .warnings(false)
        .compile("perifrac_openvdb_shim");
    for lib in ["openvdb", "Imath-3_1", "tbb"] {
        println!("cargo:rustc-link-lib=dylib={lib}");
    }
}
