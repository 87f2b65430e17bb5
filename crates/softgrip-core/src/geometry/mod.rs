//! Geometry with no physics in it, below everything else: a grid of facets for near-facet
//! queries, and the point of a triangle closest to a point. The contact stage and the model's
//! self-collision set-up share them.

mod facet_grid;
mod triangle;

pub use facet_grid::FacetGrid;
pub use triangle::closest_point_on_triangle;
