//! `cargo xtask`: the front end of signorini's studies, tests and docs (the
//! code is the library's, `xtask::main`).

fn main() -> std::process::ExitCode {
    xtask::main()
}
