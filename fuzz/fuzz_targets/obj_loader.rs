//! OBJ (+ MTL) text from memory through the loader, then rendered; see
//! `shadelab_raster::fuzzing::obj_loader` for the input format and the invariants.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    shadelab_raster::fuzzing::obj_loader(data);
});
