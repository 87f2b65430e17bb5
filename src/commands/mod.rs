//! The command line: `Cli` and its `Command`s, and the dispatch. Each
//! command has its own file with its clap `Args` (whose doc comment is the
//! command's description) and its `run`; the argument blocks several
//! commands share are in `args`. Errors are reported once, here, with
//! `anyhow`. See README.md for the commands in use.

use std::process::ExitCode;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};

mod args;
mod bench;
mod check;
mod compare;
mod diagnose;
mod errors;
mod figures;
mod fit;
mod grasp;
mod grasp_window;
mod load;
mod merge;
mod mesh;
mod modulus;
mod outputs;
mod progress;
mod prove;
mod ramp;
mod run;
mod scene;
#[cfg(feature = "gui")]
mod screenshot;
mod sweep;
mod synth;
mod values;
#[cfg(feature = "gui")]
mod view;

#[derive(Parser)]
#[command(
    name = "softgrip",
    version,
    about = "Soft-object grasp simulation (mass-spring-damper model with Hunt-Crossley contact)"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Tetrahedra a scene's mesh may have: an edge length that would make more is refused
    /// before anything is built, with the count and the memory (about 530 bytes each).
    #[arg(long, global = true, value_name = "N", default_value_t = softgrip_core::mesh::budget::DEFAULT_MAX_TETRAHEDRA)]
    max_tetrahedra: u64,
}

// In the order `softgrip --help` lists them. A doc comment here would
// replace the program's description.
#[derive(Subcommand)]
enum Command {
    Run(run::Args),
    Ramp(ramp::Args),
    Check(check::Args),
    Scene(scene::Args),
    Compare(compare::Args),
    Sweep(sweep::Args),
    Merge(merge::Args),
    Synth(synth::Args),
    Fit(fit::Args),
    Modulus(modulus::Args),
    Diagnose(diagnose::Args),
    Prove(prove::Args),
    Grasp(grasp::Args),
    Mesh(mesh::Args),
    #[cfg(feature = "gui")]
    View(view::Args),
    #[cfg(feature = "gui")]
    Screenshot(screenshot::Args),
    Bench(bench::Args),
}

/// Every option that takes a value takes a negative number too (`--loads -3`, `--offset -0.01`):
/// clap would otherwise read `-3` as a flag and advise `-- -3`, which does not work after an
/// option.
fn with_negative_numbers(command: clap::Command) -> clap::Command {
    command
        .mut_args(|a| {
            let takes = a.get_action().takes_values();
            a.allow_negative_numbers(takes)
        })
        .mut_subcommands(with_negative_numbers)
}

pub fn main() -> ExitCode {
    let matches = with_negative_numbers(Cli::command()).get_matches();
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    softgrip_core::mesh::budget::set_max_tetrahedra(cli.max_tetrahedra);
    let result = match cli.command {
        #[cfg(feature = "gui")]
        None => view::open_thesis_scene(),
        #[cfg(not(feature = "gui"))]
        None => run::without_viewer(),
        Some(Command::Run(args)) => run::run(args),
        Some(Command::Ramp(args)) => ramp::run(args),
        Some(Command::Check(args)) => check::run(args),
        Some(Command::Scene(args)) => scene::run(args),
        Some(Command::Compare(args)) => compare::run(args),
        Some(Command::Sweep(args)) => sweep::run(args),
        Some(Command::Merge(args)) => merge::run(args),
        Some(Command::Synth(args)) => synth::run(args),
        Some(Command::Fit(args)) => fit::run(args),
        Some(Command::Modulus(args)) => modulus::run(args),
        Some(Command::Diagnose(args)) => diagnose::run(args),
        Some(Command::Prove(args)) => prove::run(args),
        Some(Command::Grasp(args)) => grasp::run(args),
        Some(Command::Mesh(args)) => mesh::run(args),
        #[cfg(feature = "gui")]
        Some(Command::View(args)) => view::run(args),
        #[cfg(feature = "gui")]
        Some(Command::Screenshot(args)) => screenshot::run(args),
        Some(Command::Bench(args)) => bench::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        // An answer already printed whose exit code carries it (`grasp`: slipping, dropped).
        Err(e) if e.downcast_ref::<errors::Outcome>().is_some() => {
            ExitCode::from(e.downcast_ref::<errors::Outcome>().map_or(1, |o| o.0))
        }
        Err(e) => {
            eprintln!("error: {}", errors::error_text(&e));
            ExitCode::FAILURE
        }
    }
}
