//! `softgrip scene`: the built-in thesis scene as TOML.

use anyhow::Result;

/// Print the built-in thesis scene as TOML (a starting point for your own).
#[derive(clap::Args)]
pub struct Args {}

pub fn run(_args: Args) -> Result<()> {
    print!("{}", softgrip_core::scene::THESIS_SCENE);
    Ok(())
}
