//! `[support]`: what holds the object (its fixed bottom, a table, or nothing) and the friction.

use super::resolver::{At, Resolver};
use crate::scene::error::SceneError;
use crate::scene::raw::RawSupport;
use crate::scene::{Support, SupportKind};

impl Resolver<'_> {
    pub(super) fn support(&mut self, sup: RawSupport) -> Result<Support, SceneError> {
        let at = |key| At {
            table: "support",
            index: None,
            key,
        };
        let kind_at = at("kind");
        let kind = match self
            .default(kind_at, sup.kind, "fixed-bottom".to_string())
            .as_str()
        {
            "fixed-bottom" => SupportKind::FixedBottom,
            "table" => SupportKind::Table,
            "none" => SupportKind::None,
            other => {
                return Err(self.err(
                    kind_at,
                    format!("{other:?}"),
                    "must be \"fixed-bottom\", \"table\" or \"none\"",
                ));
            }
        };
        let friction = self.number(
            at("friction"),
            sup.friction,
            0.0,
            |x| x >= 0.0,
            "must be >= 0 (a Coulomb coefficient)",
        )?;
        Ok(Support { kind, friction })
    }
}
