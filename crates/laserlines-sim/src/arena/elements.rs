//! The element types of the RoboCup Rescue arena set and their geometry, as facts read from
//! the public models of `tu-darmstadt-ros-pkg/hector_nist_arenas_gazebo`
//! (`hector_nist_arena_elements/elements/*/properties.xml` and the COLLADA meshes in
//! `hector_nist_arena_elements/Media/models/`, with each mesh's node transform applied).
//!
//! Every shape is given in the element's own frame at rotation 0: the cell centre at the
//! origin, x along the cell's `+y` edge, metres, heights above the floor. The loader turns it
//! by `-R` degrees about the cell centre (as the arena designer does) and cuts it at the
//! laser's height ([`super::cut`]).

/// A solid of an element, element frame (see the [module docs](self)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Solid {
    /// A thin vertical plate from `a` to `b`, from height `z[0]` to `z[1]`.
    Plate {
        a: [f64; 2],
        b: [f64; 2],
        z: [f64; 2],
    },
    /// A box with sides along the axes, `min` to `max`, from height `z[0]` to `z[1]`.
    Block {
        min: [f64; 2],
        max: [f64; 2],
        z: [f64; 2],
    },
    /// Half a barrel: the half cylinder of `radius` whose flat side lies on the line
    /// `y = centre[1]`, bulging towards `-y` (into the cell), from `z[0]` to `z[1]`.
    HalfBarrel {
        centre: [f64; 2],
        radius: f64,
        z: [f64; 2],
    },
    /// A solid ramp over `x[0]..x[1]`: its surface rises from the floor at `y = y0` to
    /// `top` at `y = y1`, where a vertical face closes it.
    Wedge {
        x: [f64; 2],
        y0: f64,
        y1: f64,
        top: f64,
    },
    /// A board `thickness` thick (vertically) over `x[0]..x[1]`, its underside rising from
    /// the floor at `y = y0` to `top` at `y = y1`.
    Board {
        x: [f64; 2],
        y0: f64,
        y1: f64,
        top: f64,
        thickness: f64,
    },
}

/// A hole through a wall plate: a stadium of `radius` around the segment from `x[0]` to
/// `x[1]` (along the wall) at height `z` (a round hole when `x[0] == x[1]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Hole {
    pub(crate) x: [f64; 2],
    pub(crate) z: f64,
    pub(crate) radius: f64,
}

/// Where a mountable item sits on a wall: `along` m from the wall's left end (looking at
/// the `+y` edge from the cell), `z` m above the floor (`properties.xml`,
/// `<item-mount-point x= y=>`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct MountPoint {
    pub(crate) along: f64,
    pub(crate) z: f64,
}

/// What an element type is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Kind {
    /// A wall plate on the cell's `+y` edge from the floor to at least 1.2 m, as long as
    /// [`super::WallLength`] says, with its holes and the mount points of its items.
    Wall {
        holes: &'static [Hole],
        mounts: &'static [MountPoint],
    },
    /// Solids standing in the cell.
    Solids(&'static [Solid]),
    /// An item mounted on the wall of its cell with the same rotation (at one of that
    /// wall's mount points), or standing on the floor at the cell centre when there is none;
    /// its solids relative to that place.
    Mountable(&'static [Solid]),
    /// Known, and nothing of it is higher than `top` m; its shape below that is not
    /// modelled (step fields, floor tiles, small items lying on the floor).
    Low { top: f64 },
}

/// One element type of the set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ElementType {
    pub(crate) name: &'static str,
    pub(crate) kind: Kind,
}

const NO_HOLES: &[Hole] = &[];
const NO_MOUNTS: &[MountPoint] = &[];

/// `wall_holes1` (mesh `small_wall_holes1.dae`): three round holes of 7.5 cm radius.
const HOLES1: &[Hole] = &[
    Hole {
        x: [-0.280, -0.280],
        z: 0.309,
        radius: 0.075,
    },
    Hole {
        x: [-0.290, -0.290],
        z: 0.896,
        radius: 0.075,
    },
    Hole {
        x: [0.289, 0.289],
        z: 0.591,
        radius: 0.075,
    },
];

/// `small_wall_triple_holes`: three slots 0.36 m x 0.15 m with round ends.
const TRIPLE_HOLES: &[Hole] = &[
    Hole {
        x: [-0.366, -0.154],
        z: 0.273,
        radius: 0.075,
    },
    Hole {
        x: [0.203, 0.415],
        z: 0.620,
        radius: 0.075,
    },
    Hole {
        x: [-0.347, -0.135],
        z: 0.901,
        radius: 0.075,
    },
];

/// Mount points of `wall_holes1` and `small_wall_triple_holes`: top left, middle, bottom
/// left (behind the holes).
const HOLE_MOUNTS: &[MountPoint] = &[
    MountPoint { along: 0.3, z: 0.9 },
    MountPoint { along: 0.9, z: 0.6 },
    MountPoint { along: 0.3, z: 0.3 },
];

/// Mount points of `small_wall_start_check`: left, middle, right.
const START_CHECK_MOUNTS: &[MountPoint] = &[
    MountPoint { along: 0.9, z: 0.6 },
    MountPoint { along: 0.6, z: 0.6 },
    MountPoint { along: 0.3, z: 0.6 },
];

const fn wall(name: &'static str) -> ElementType {
    ElementType {
        name,
        kind: Kind::Wall {
            holes: NO_HOLES,
            mounts: NO_MOUNTS,
        },
    }
}

const fn low(name: &'static str, top: f64) -> ElementType {
    ElementType {
        name,
        kind: Kind::Low { top },
    }
}

const fn plate(a: [f64; 2], b: [f64; 2], z: [f64; 2]) -> Solid {
    Solid::Plate { a, b, z }
}

const fn block(min: [f64; 2], max: [f64; 2], z: [f64; 2]) -> Solid {
    Solid::Block { min, max, z }
}

/// `corner_diag_120`: two plates from the cell centre to the two corners of its `+y` edge
/// (a right-angled corner turned by 45 degrees), 1.2 m high.
const CORNER_DIAG: &[Solid] = &[
    plate([0.0, 0.0], [0.6, 0.6], [0.0, 1.2]),
    plate([0.0, 0.0], [-0.6, 0.6], [0.0, 1.2]),
];

/// `wall_diag_120`: one plate along the cell's diagonal, 1.2 m high.
const WALL_DIAG: &[Solid] = &[plate([-0.6, -0.6], [0.6, 0.6], [0.0, 1.2])];

/// `fiducial_barrel`, `red_barrel`: a half barrel of 0.29 m radius on the `+y` edge, from
/// 0.30 m to 1.19 m (two of them, back to back on one edge, make a whole barrel).
const HALF_BARREL: &[Solid] = &[Solid::HalfBarrel {
    centre: [0.0, 0.59],
    radius: 0.29,
    z: [0.30, 1.19],
}];

/// `fiducial_barrel_high`: the same half barrel 1.2 m higher, on an elevated floor.
const HALF_BARREL_HIGH: &[Solid] = &[Solid::HalfBarrel {
    centre: [0.0, 0.59],
    radius: 0.29,
    z: [1.50, 2.39],
}];

/// `veil_wall`: nine hanging strips 2 cm wide on the `+y` edge (a bar across the top from
/// 1.14 m to 1.2 m).
const VEIL: &[Solid] = &[
    plate([0.492, 0.594], [0.512, 0.594], [0.0, 1.15]),
    plate([0.360, 0.594], [0.380, 0.594], [0.013, 1.16]),
    plate([0.226, 0.594], [0.246, 0.594], [0.007, 1.16]),
    plate([0.096, 0.594], [0.116, 0.594], [0.0, 1.15]),
    plate([-0.031, 0.594], [-0.011, 0.594], [0.039, 1.16]),
    plate([-0.156, 0.594], [-0.136, 0.594], [0.0, 1.16]),
    plate([-0.288, 0.594], [-0.268, 0.594], [0.081, 1.16]),
    plate([-0.412, 0.594], [-0.392, 0.594], [0.008, 1.17]),
    plate([-0.554, 0.594], [-0.534, 0.594], [0.011, 1.17]),
    plate([-0.6, 0.6], [0.6, 0.6], [1.14, 1.2]),
];

/// `elevated_floor_120`: a table over the whole cell, its top from 1.08 m to 1.2 m, on four
/// legs of 0.1 m x 0.1 m in the corners.
const ELEVATED_FLOOR: &[Solid] = &[
    block([0.49, 0.49], [0.59, 0.59], [0.0, 1.08]),
    block([-0.59, 0.49], [-0.49, 0.59], [0.0, 1.08]),
    block([-0.59, -0.59], [-0.49, -0.49], [0.0, 1.08]),
    block([0.49, -0.59], [0.59, -0.49], [0.0, 1.08]),
    block([-0.59, -0.59], [0.59, 0.59], [1.08, 1.2]),
];

/// `simple_elev_ramp`: a board 2 cm thick from the floor at the `-y` edge up to 1.18 m at
/// the `+y` edge (the way onto an elevated floor), nothing under it.
const ELEV_RAMP: &[Solid] = &[Solid::Board {
    x: [-0.59, 0.59],
    y0: -0.59,
    y1: 0.59,
    top: 1.18,
    thickness: 0.02,
}];

/// `full_ramp`: a solid ramp over the whole cell, from the floor at the `+y` edge up to
/// 0.339 m at the `-y` edge (15 degrees).
const FULL_RAMP: &[Solid] = &[Solid::Wedge {
    x: [-0.59, 0.59],
    y0: 0.59,
    y1: -0.59,
    top: 0.339,
}];

/// `half_ramp`: a solid ramp over the `-y` half of the cell, from the floor at the `-y`
/// edge up to 0.17 m at the cell's centre line (two back to back make a ridge).
const HALF_RAMP: &[Solid] = &[Solid::Wedge {
    x: [-0.59, 0.59],
    y0: -0.59,
    y1: 0.0,
    top: 0.170,
}];

/// `stairs_120`: five treads 3 cm thick across the cell, rising towards `+y` from 0.2 m to
/// 1.0 m, with nothing between them (no risers).
const STAIRS: &[Solid] = &[
    block([-0.59, -0.590], [0.59, -0.340], [0.200, 0.230]),
    block([-0.59, -0.3575], [0.59, -0.1075], [0.400, 0.430]),
    block([-0.59, -0.125], [0.59, 0.125], [0.600, 0.630]),
    block([-0.59, 0.1075], [0.59, 0.3575], [0.800, 0.830]),
    block([-0.59, 0.340], [0.59, 0.590], [1.000, 1.030]),
];

/// `manip_storage`: two shelves 1 cm thick over the whole cell at 0.5 m and 1.0 m, with no
/// legs in the model.
const MANIP_STORAGE: &[Solid] = &[
    block([-0.59, -0.59], [0.59, 0.59], [0.495, 0.505]),
    block([-0.59, -0.59], [0.59, 0.59], [0.995, 1.005]),
];

/// `spectator_120`: a box from 1.07 m to 1.70 m above the floor near the `+y` edge.
const SPECTATOR: &[Solid] = &[block([-0.213, 0.077], [0.213, 0.533], [1.069, 1.700])];

/// `victim_with_box1`: a box 0.5 m wide, 0.24 m deep and 0.4 m high against the wall,
/// centred on its place (mount point or floor).
const VICTIM_BOX: &[Solid] = &[block([-0.25, 0.35], [0.25, 0.59], [-0.2, 0.2])];

/// The element types the loader knows.
pub(crate) const TYPES: &[ElementType] = &[
    wall("small_wall"),
    wall("small_wall_no_tex"),
    wall("small_wall_qr"),
    wall("small_wall_gap_no_tex"),
    wall("tall_wall"),
    ElementType {
        name: "small_wall_start_check",
        kind: Kind::Wall {
            holes: NO_HOLES,
            mounts: START_CHECK_MOUNTS,
        },
    },
    ElementType {
        name: "wall_holes1",
        kind: Kind::Wall {
            holes: HOLES1,
            mounts: HOLE_MOUNTS,
        },
    },
    ElementType {
        name: "small_wall_triple_holes",
        kind: Kind::Wall {
            holes: TRIPLE_HOLES,
            mounts: HOLE_MOUNTS,
        },
    },
    solids("veil_wall", VEIL),
    solids("corner_diag_120", CORNER_DIAG),
    solids("wall_diag_120", WALL_DIAG),
    solids("fiducial_barrel", HALF_BARREL),
    solids("red_barrel", HALF_BARREL),
    solids("fiducial_barrel_high", HALF_BARREL_HIGH),
    solids("elevated_floor_120", ELEVATED_FLOOR),
    solids("simple_elev_ramp", ELEV_RAMP),
    solids("full_ramp", FULL_RAMP),
    solids("half_ramp", HALF_RAMP),
    solids("stairs_120", STAIRS),
    solids("manip_storage", MANIP_STORAGE),
    solids("spectator_120", SPECTATOR),
    ElementType {
        name: "victim_with_box1",
        kind: Kind::Mountable(VICTIM_BOX),
    },
    // Posts of 0.1 m x 0.1 m, the highest 0.40 m (mesh scaled by 0.5).
    low("stepfield_red_diagonal", 0.40),
    // Heights from the elements' properties.xml (meta-info "Height").
    low("stepfield", 0.5),
    low("half_ramp_shifted", 0.178),
    low("elevated_ramps", 0.256),
    low("victim_1", 0.2),
    low("wooden_block", 0.1),
    low("sand_wheel", 0.05),
    low("readiness_test", 0.305),
    low("pvc_pipe", 0.6),
];

const fn solids(name: &'static str, solids: &'static [Solid]) -> ElementType {
    ElementType {
        name,
        kind: Kind::Solids(solids),
    }
}

/// The type called `name`, if the loader knows it.
pub(crate) fn element_type(name: &str) -> Option<&'static ElementType> {
    TYPES.iter().find(|t| t.name == name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_shapes_sound() {
        for (i, t) in TYPES.iter().enumerate() {
            assert!(
                TYPES[i + 1..].iter().all(|u| u.name != t.name),
                "{} twice",
                t.name
            );
            let check = |s: &Solid| match *s {
                Solid::Plate { z, .. } | Solid::Block { z, .. } | Solid::HalfBarrel { z, .. } => {
                    assert!(z[0] < z[1], "{}", t.name);
                }
                Solid::Wedge { top, .. } | Solid::Board { top, .. } => {
                    assert!(top > 0.0, "{}", t.name);
                }
            };
            match t.kind {
                Kind::Solids(s) | Kind::Mountable(s) => s.iter().for_each(check),
                Kind::Wall { holes, .. } => {
                    for h in holes {
                        assert!(h.x[0] <= h.x[1] && h.radius > 0.0, "{}", t.name);
                    }
                }
                Kind::Low { top } => assert!(top > 0.0),
            }
        }
        assert!(element_type("wall_diag_120").is_some());
        assert!(element_type("nothing_like_it").is_none());
    }
}
