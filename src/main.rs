//! The `softgrip` command line. See README.md.

mod cli;

fn main() -> std::process::ExitCode {
    cli::main()
}
