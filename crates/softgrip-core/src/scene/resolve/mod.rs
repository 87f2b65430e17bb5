//! The raw tables to a [`Scene`]: each table resolved by its own function (one file per table),
//! in file order, through the shared value checks of `resolver`. The order matters: it is the
//! order of `Scene::defaults_applied` and decides which of several errors is reported.

mod boxes;
mod finger;
mod grasp;
mod model;
mod object;
mod resolver;
mod simulation;
mod support;

use resolver::Resolver;

use super::Scene;
use super::error::SceneError;
use super::raw::RawScene;

/// Resolves `raw`, parsed from `text` (searched for the line of a bad key); `file` names it in
/// errors.
pub(super) fn resolve(raw: RawScene, text: &str, file: &str) -> Result<Scene, SceneError> {
    let mut resolver = Resolver::new(text, file);
    let simulation = resolver.simulation(raw.simulation.unwrap_or_default())?;
    let object = resolver.object(raw.object)?;
    let model = resolver.model(raw.model.unwrap_or_default())?;
    let support = resolver.support(raw.support.unwrap_or_default())?;
    let fixed = resolver.fixed(&raw.fixed)?;
    let loads = resolver.loads(&raw.load)?;
    let fingers = resolver.fingers(&raw.finger)?;
    let regions = resolver.regions(&raw.region, &object)?;
    let grasp = resolver.grasp(raw.grasp.unwrap_or_default())?;
    Ok(Scene {
        simulation,
        object,
        model,
        support,
        fixed,
        loads,
        fingers,
        regions,
        grasp,
        source: None,
        defaults_applied: resolver.applied,
    })
}
