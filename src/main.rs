//! The `softgrip` command line. See README.md.

mod commands;

fn main() -> std::process::ExitCode {
    commands::main()
}
