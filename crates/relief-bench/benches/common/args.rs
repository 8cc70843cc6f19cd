//! The arguments a benchmark program was given, as `cargo bench -p relief-bench --bench NAME --
//! ARGS` passes them.

/// The program's arguments after its name, less the `--bench` flag `cargo bench` adds.
pub fn program_args() -> Vec<String> {
    std::env::args().skip(1).filter(|a| a != "--bench").collect()
}
