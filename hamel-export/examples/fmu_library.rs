//! The FMU library of a catalogue model, for hamel's `export` example (`cargo run --release
//! --example export -- fmu MODEL OUTDIR`), which writes the model's two lines
//! (`hamel_export::model!` and `hamel_export::fmi2!`) into `$HAMEL_FMU_SOURCE/library.rs`
//! and builds this example with the feature `catalogue-fmu`. Built in hamel's workspace with
//! its release profile, it links the runtime and the catalogue the robot example built,
//! rather than building them again.
include!(concat!(
    env!(
        "HAMEL_FMU_SOURCE",
        "set by hamel's `export` example: the directory of the model's library.rs"
    ),
    "/library.rs"
));
