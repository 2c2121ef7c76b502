//! Arbitrary small scenes, cameras and options through the whole pipeline; see
//! `shadelab_raster::fuzzing::pipeline` for the decoding and the invariants.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    shadelab_raster::fuzzing::pipeline(data);
});
