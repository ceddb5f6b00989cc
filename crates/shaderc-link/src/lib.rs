//! Empty on purpose: this crate exists for its build script, which adds the static libraries
//! that Debian's `libshaderc` leaves out (see `build.rs`). lensray's build script depends on it
//! next to `shaderc`, so the shader compiler links on Debian 12 without building shaderc.
