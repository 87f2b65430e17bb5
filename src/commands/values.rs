//! The library's enums as command-line values. clap lives in the binary only: each wrapper
//! names its values and their help here, and hands the library's own enum on (`.0`).

use clap::builder::PossibleValue;

/// Declares a wrapper `$name($core)` that clap parses as one of the listed values, each with
/// its help line (shown by `--help`) where one is given.
macro_rules! value_enum {
    ($(#[$meta:meta])* $name:ident($core:ty) {
        $($variant:ident = $value:literal $(: $help:literal)?,)*
    }) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        pub struct $name(pub $core);

        impl clap::ValueEnum for $name {
            fn value_variants<'a>() -> &'a [Self] {
                &[$($name(<$core>::$variant)),*]
            }

            fn to_possible_value(&self) -> Option<PossibleValue> {
                Some(match self.0 {
                    $(<$core>::$variant => PossibleValue::new($value)$(.help($help))?,)*
                })
            }
        }
    };
}

value_enum! {
    /// `--format` of `mesh convert` and `mesh make`.
    MeshFormat(softgrip_core::mesh::io::Format) {
        Msh = "msh": "Gmsh 4.1 ASCII (`.msh`; reading also takes 2.2 and binary)",
        Msh22 = "msh22": "Gmsh 2.2 ASCII (`.msh`)",
        Tetgen = "tetgen": "TetGen `.node` + `.ele` (+ `.face`), named by either file",
        Vtk = "vtk": "VTK legacy ASCII unstructured grid (`.vtk`; reading also takes binary and version 5.1)",
        Vtu = "vtu": "VTK XML unstructured grid (`.vtu`, ASCII; reading also takes inline binary, appended and zlib-compressed data)",
    }
}

value_enum! {
    /// `run --surface`.
    SurfaceFormat(softgrip_core::output::surface::SurfaceFormat) {
        Stl = "stl",
        Obj = "obj",
    }
}

#[cfg(feature = "gui")]
value_enum! {
    /// `screenshot --color`.
    Field(softgrip_core::fields::Field) {
        Displacement = "displacement": "Distance from the rest position (m)",
        SpringStrain = "spring-strain": "Strain `(l - l0) / l0` of the spring at each particle with the largest magnitude, signed (stretch > 0, compression < 0)",
        VolumeChange = "volume-change": "Element volume change `V / V0 - 1`, averaged (volume-weighted) over the elements at each particle",
        ContactPressure = "contact-pressure": "Contact normal force per unit area at each boundary particle (Pa): each contact's force shared by its barycentric weights, divided by the particle's share (a third) of the area of its boundary facets",
        YoungModulus = "young-modulus": "The material's Young's modulus (Pa), volume-weighted over the elements at each particle: shows `[[region]]`s",
        GreenStrain = "green-strain": "The largest principal Green strain of the elements at each particle, the largest of them: where a tear would start",
        VonMises = "von-mises": "The von Mises stress (Pa) of the elements at each particle, the largest of them",
    }
}

#[cfg(feature = "gui")]
value_enum! {
    /// `screenshot --view`.
    View(softgrip_viewer::render::View) {
        Front = "front": "Looking along +y (from the front, -y side)",
        Side = "side": "Looking along -x (from the +x side)",
        Top = "top": "Looking down -z",
        Iso = "iso": "From the front right, above",
    }
}
