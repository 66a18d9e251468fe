//! The command line of a catalogue model's FMU (`hamel_export::fmi2::tool`: its
//! `modelDescription.xml`, hamel's own run of the model), for hamel's `export` example,
//! which writes its source into `$HAMEL_FMU_SOURCE/tool.rs` (see `fmu_library.rs`).
include!(concat!(
    env!(
        "HAMEL_FMU_SOURCE",
        "set by hamel's `export` example: the directory of the model's tool.rs"
    ),
    "/tool.rs"
));
