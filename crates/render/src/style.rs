//! The style sheet of every picture: each legend entry ([`Layer`]) with its look (fill, stroke,
//! width, opacity), its label and its marker shape, and the colour scale of margins. Pictures
//! draw only through these entries, so a legend cannot disagree with its picture.

/// The legend entries, each with its fixed look.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Layer {
    /// The map boundary.
    Boundary,
    /// Obstacles, filled grey.
    Obstacle,
    /// BTM edges, thin.
    BtmEdge,
    /// A sleeve, shaded.
    Sleeve,
    /// The taut tether (SHP), bold.
    Shp,
    /// Tether anchors, squares.
    Anchor,
    /// Friction cones, translucent wedges.
    FrictionCone,
    /// Visibility lines.
    Visibility,
    /// The ascent path.
    Ascent,
    /// The descent path.
    Descent,
    /// Waypoints, stars.
    Waypoint,
    /// Other paths (input paths).
    Path,
    /// The start.
    Start,
    /// The goal.
    Goal,
    /// Terrain shading (hillshade) under the map.
    Terrain,
    /// Edges between terrain planes.
    PlaneEdge,
    /// Robot obstacles the tether passes over (negative obstacles), outlined.
    RobotObstacle,
    /// A stable pose (stability maps), green dot.
    Stable,
    /// An unstable pose (stability maps), red dot.
    Unstable,
    /// A PTFO not touched by the shown tether, outlined.
    Ptfo,
    /// A PTFO the tether sticks on (solid), green.
    PtfoSolid,
    /// A PTFO the tether slides over, pale.
    PtfoSlides,
    /// A volatile PTFO (the class is unsafe), red.
    PtfoVolatile,
    /// A sticking point: a solid friction anchor.
    Sticking,
    /// A PTFO vertex clipped after a slip.
    Slip,
    /// A convex terrain cell (thesis Fig. 3.11), green.
    Convex,
    /// A concave terrain cell, red.
    Concave,
    /// A saddle cell, blue.
    Saddle,
    /// A direction along which a saddle is convex (thesis Fig. 3.12), cyan.
    ConvexDirection,
    /// A tether sample where sticking is possible (thesis Fig. 3.13), black.
    MayStick,
    /// A tether sample where the tether slips whatever the tensions, red.
    WillSlip,
    /// The taut tether of a class whose ascent is infeasible.
    InfeasibleShp,
    /// The anchor (or the goal) that blocks a class's ascent.
    Blocking,
    /// Where the robot is (online runs), a circle.
    Robot,
    /// A stable cell of a mesh stability map, filled by its margin on the colour scale.
    StableCell,
    /// An unstable cell of a mesh stability map, grey.
    UnstableCell,
    /// The holding robot's path (Kumar's Robot 1).
    HoldingPath,
    /// The descending robot's path (Kumar's Robot 2).
    DescendingPath,
    /// A terrain surface of a multi-slope terrain, shaded by its slope.
    Surface,
}

/// How a layer is drawn, and so how its legend entry looks: the picture and the legend both
/// read it here.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Glyph {
    /// Filled areas (polygons), shown as a filled box.
    Area,
    /// Lines, shown as a line of the layer's width.
    Line,
    /// A marker of fixed on-screen size at a point, shown as that marker.
    Mark(Marker),
    /// A disc sized in map units (stability dots), shown as a disc.
    Disc,
}

impl Layer {
    /// A second, small legend line where a reader needs it to read the layer right (the
    /// friction cones' drawn radius).
    pub(crate) fn legend_note(self) -> Option<String> {
        match self {
            Layer::FrictionCone => Some(format!("radius {}x the tether below", CONE_DRAW_FACTOR)),
            _ => None,
        }
    }

    /// The legend text of the layer.
    pub fn label(self) -> &'static str {
        match self {
            Layer::Boundary => "map boundary",
            Layer::Obstacle => "obstacle",
            Layer::BtmEdge => "BTM edge",
            Layer::Sleeve => "sleeve",
            Layer::Shp => "taut tether (SHP)",
            Layer::Anchor => "anchor",
            Layer::FrictionCone => "friction cone",
            Layer::Visibility => "visibility line",
            Layer::Ascent => "ascent path",
            Layer::Descent => "descent path",
            Layer::Waypoint => "waypoint",
            Layer::Path => "path",
            Layer::Start => "start",
            Layer::Goal => "goal",
            Layer::Terrain => "hillshade",
            Layer::PlaneEdge => "plane edge",
            Layer::RobotObstacle => "robot obstacle",
            Layer::Stable => "stable pose",
            Layer::Unstable => "unstable pose",
            Layer::Ptfo => "PTFO (untouched)",
            Layer::PtfoSolid => "PTFO: solid",
            Layer::PtfoSlides => "PTFO: slides",
            Layer::PtfoVolatile => "PTFO: volatile",
            Layer::Sticking => "sticking point",
            Layer::Slip => "clipped vertex (slip)",
            Layer::Convex => "convex",
            Layer::Concave => "concave",
            Layer::Saddle => "saddle",
            Layer::ConvexDirection => "saddle's convex direction",
            Layer::MayStick => "tether may stick",
            Layer::WillSlip => "tether slips",
            Layer::InfeasibleShp => "infeasible class (SHP)",
            Layer::Blocking => "blocking anchor",
            Layer::Robot => "robot",
            Layer::StableCell => "stable cell",
            Layer::UnstableCell => "unstable cell",
            Layer::HoldingPath => "robot 1 path (holding)",
            Layer::DescendingPath => "robot 2 path",
            Layer::Surface => "surface (darker: steeper)",
        }
    }

    /// How the layer is drawn (and its legend entry): the one place a marker's shape is chosen.
    pub fn glyph(self) -> Glyph {
        match self {
            Layer::Start | Layer::Slip => Glyph::Mark(Marker::Cross),
            Layer::Goal | Layer::Blocking | Layer::Robot | Layer::MayStick | Layer::WillSlip => {
                Glyph::Mark(Marker::Circle)
            }
            Layer::Anchor | Layer::Sticking => Glyph::Mark(Marker::Square),
            Layer::Waypoint => Glyph::Mark(Marker::Star),
            Layer::Stable | Layer::Unstable => Glyph::Disc,
            Layer::Boundary
            | Layer::BtmEdge
            | Layer::Shp
            | Layer::Visibility
            | Layer::Ascent
            | Layer::Descent
            | Layer::Path
            | Layer::PlaneEdge
            | Layer::Ptfo
            | Layer::ConvexDirection
            | Layer::InfeasibleShp
            | Layer::HoldingPath
            | Layer::DescendingPath => Glyph::Line,
            Layer::Obstacle
            | Layer::Sleeve
            | Layer::FrictionCone
            | Layer::Terrain
            | Layer::RobotObstacle
            | Layer::PtfoSolid
            | Layer::PtfoSlides
            | Layer::PtfoVolatile
            | Layer::Convex
            | Layer::Concave
            | Layer::Saddle
            | Layer::StableCell
            | Layer::UnstableCell
            | Layer::Surface => Glyph::Area,
        }
    }

    /// Drawing order, lowest first (the legend lists layers in the same order).
    pub(crate) fn draw_order(self) -> u8 {
        match self {
            Layer::Terrain | Layer::Convex | Layer::Concave | Layer::Saddle => 0,
            Layer::StableCell | Layer::UnstableCell | Layer::Surface => 0,
            Layer::HoldingPath | Layer::DescendingPath => 6,
            Layer::ConvexDirection => 1,
            Layer::RobotObstacle => 1,
            Layer::PlaneEdge => 5,
            Layer::Sleeve => 0,
            Layer::FrictionCone => 1,
            Layer::BtmEdge => 2,
            Layer::Obstacle => 3,
            Layer::Boundary => 4,
            Layer::Visibility => 5,
            Layer::Path => 6,
            Layer::Descent => 7,
            Layer::Ascent => 8,
            Layer::Shp => 9,
            Layer::Anchor => 10,
            Layer::Waypoint => 11,
            // Below the obstacles: a dot near an edge never hides one.
            Layer::Stable => 2,
            Layer::Unstable => 2,
            Layer::Robot => 13,
            Layer::Start => 14,
            Layer::Goal => 15,
            Layer::Ptfo | Layer::PtfoSolid | Layer::PtfoSlides | Layer::PtfoVolatile => 4,
            Layer::Sticking | Layer::MayStick | Layer::WillSlip => 11,
            Layer::Slip => 11,
            Layer::InfeasibleShp => 8,
            Layer::Blocking => 12,
        }
    }

    /// The layer's fill colour (`none` for stroked layers).
    pub fn fill(self) -> &'static str {
        self.look().0
    }

    /// (fill, stroke, stroke width in px, fill opacity)
    pub(crate) fn look(self) -> (&'static str, &'static str, f64, f64) {
        match self {
            Layer::Boundary => ("none", "#222222", 1.5, 0.0),
            Layer::Obstacle => ("#8c8c8c", "#555555", 0.6, 1.0),
            Layer::BtmEdge => ("none", "#6a8caf", 0.35, 0.0),
            Layer::Sleeve => ("#9ecae1", "none", 0.0, 0.55),
            Layer::Shp => ("none", "#08306b", 2.6, 0.0),
            Layer::Anchor => ("#ffd92f", "#8a6d00", 0.8, 1.0),
            Layer::FrictionCone => ("#74c476", "#238b45", 0.5, 0.22),
            Layer::Visibility => ("none", "#41b6c4", 0.8, 0.0),
            Layer::Ascent => ("none", "#d95f02", 1.6, 0.0),
            Layer::Descent => ("none", "#7570b3", 1.6, 0.0),
            Layer::Waypoint => ("#e7298a", "#67001f", 0.5, 1.0),
            Layer::Path => ("none", "#e6550d", 1.2, 0.0),
            Layer::Start => ("#d62728", "#7f0000", 0.8, 1.0),
            Layer::Goal => ("#2ca02c", "#00441b", 0.8, 1.0),
            Layer::Terrain => ("#bbbbbb", "none", 0.0, 1.0),
            Layer::PlaneEdge => ("none", "#b15928", 1.4, 0.0),
            Layer::RobotObstacle => ("#fdbf6f", "#ff7f00", 0.8, 0.35),
            Layer::Stable => ("#21918c", "#1b1b1b", 0.3, 1.0),
            Layer::Unstable => ("none", "#444444", 0.9, 0.0),
            Layer::Ptfo => ("none", "#6a3d9a", 1.2, 0.0),
            Layer::PtfoSolid => ("#41ab5d", "#005a32", 1.0, 0.8),
            Layer::PtfoSlides => ("#fee8c8", "#e34a33", 1.0, 0.6),
            Layer::PtfoVolatile => ("#de2d26", "#67000d", 1.2, 0.8),
            Layer::Sticking => ("#00441b", "#00ff7f", 0.8, 1.0),
            Layer::Slip => ("#e6550d", "#7f2704", 1.2, 1.0),
            Layer::Convex => ("#41ab5d", "none", 0.0, 0.85),
            Layer::Concave => ("#de2d26", "none", 0.0, 0.85),
            Layer::Saddle => ("#3182bd", "none", 0.0, 0.85),
            Layer::ConvexDirection => ("none", "#00e5ff", 0.7, 0.0),
            Layer::MayStick => ("#000000", "#000000", 0.3, 1.0),
            Layer::WillSlip => ("#de2d26", "#67000d", 0.3, 1.0),
            Layer::InfeasibleShp => ("none", "#cb181d", 1.4, 0.0),
            Layer::Blocking => ("#cb181d", "#000000", 1.2, 1.0),
            Layer::Robot => ("#ff7f00", "#7f2704", 1.0, 1.0),
            Layer::StableCell => ("#21918c", "none", 0.0, 1.0),
            Layer::UnstableCell => ("#bdbdbd", "#636363", 0.3, 1.0),
            Layer::HoldingPath => ("none", "#1f77b4", 2.0, 0.0),
            Layer::DescendingPath => ("none", "#2ca02c", 2.0, 0.0),
            Layer::Surface => ("#c8c8c8", "#888888", 0.6, 1.0),
        }
    }
}

/// Marker shapes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Marker {
    /// A filled circle.
    Circle,
    /// A square.
    Square,
    /// A five-pointed star.
    Star,
    /// A cross.
    Cross,
}

/// How far down a friction-cone wedge is drawn, in multiples of the tether segment below its
/// anchor (the wedges of the reachable sets reach the map's edge; drawn whole they swamp a tall
/// strip).
pub const CONE_DRAW_FACTOR: f64 = 1.25;

/// The colour scale of margins (viridis at five stops, from low to high): perceptually uniform
/// and readable by colour-blind readers, unlike red against green.
pub const SCALE_STOPS: [(u8, u8, u8); 5] = [
    (68, 1, 84),
    (59, 82, 139),
    (33, 145, 140),
    (94, 201, 98),
    (253, 231, 37),
];

/// The colour of `t` in `[0, 1]` on [`SCALE_STOPS`] (clamped), as `#rrggbb`.
pub fn scale_colour(t: f64) -> String {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * (SCALE_STOPS.len() - 1) as f64;
    let i = (x.floor() as usize).min(SCALE_STOPS.len() - 2);
    let f = x - i as f64;
    let (a, b) = (SCALE_STOPS[i], SCALE_STOPS[i + 1]);
    let mix = |p: u8, q: u8| (f64::from(p) + f * (f64::from(q) - f64::from(p))).round() as u8;
    format!(
        "#{:02x}{:02x}{:02x}",
        mix(a.0, b.0),
        mix(a.1, b.1),
        mix(a.2, b.2)
    )
}
