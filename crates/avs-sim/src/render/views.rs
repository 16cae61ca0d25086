//! The picture of a room's view plan (`avs views --svg`, Sjöö et al. `004` §2.1): the cells to
//! cover, the candidate standpoints (those used filled), and every planned image as a wedge of
//! its zoomed field of view reaching as far as the cells it covers, numbered in the order
//! the plan takes them.

use super::legend::{legend_rect, scale_bar, world_legend, Legend};
use super::search::wedge_data;
use super::{compose, doors, map_size, objects, rooms, text, Frame, SCALE};
use crate::world::World;
use svg::node::element::{Circle, Group, Path, Rectangle};

/// One planned image: where the robot stands, where the camera looks, how wide and how far.
#[derive(Debug, Clone, PartialEq)]
pub struct PlannedImage {
    /// The standpoint `[x, y]`, metres.
    pub at: [f64; 2],
    /// Camera direction in the world, radians.
    pub yaw: f64,
    /// Horizontal field of view at the image's zoom, radians.
    pub hfov: f64,
    /// The wedge's length, metres (e.g. the farthest cell the image covers).
    pub reach: f64,
}

/// What a view-plan picture shows.
#[derive(Debug, Clone, PartialEq)]
pub struct ViewPlanPicture {
    /// The title.
    pub title: String,
    /// The line under it.
    pub subtitle: String,
    /// Centres of the cells to cover, and the side of a cell, metres.
    pub cells: Vec<[f64; 2]>,
    /// Side of a cell, metres.
    pub cell: f64,
    /// The candidate standpoints.
    pub standpoints: Vec<[f64; 2]>,
    /// Indices of the standpoints the plan uses.
    pub used: Vec<usize>,
    /// The images, in the order the plan takes them.
    pub images: Vec<PlannedImage>,
}

const CELL_FILL: &str = "#fdae6b";
const STANDPOINT: &str = "#636363";
const USED: &str = "#08519c";
const WEDGE: &str = "#3182bd";

/// The view plan over the world's map (rooms pale, doors, objects).
pub fn render_view_plan(world: &World, picture: &ViewPlanPicture) -> String {
    let g = &world.truth;
    let f = Frame::new(g, SCALE);
    let (w, h) = map_size(g, &f);
    let side = picture.cell * f.scale;
    let cells = picture.cells.iter().fold(Group::new(), |group, c| {
        let (x, y) = f.px(*c);
        group.add(
            Rectangle::new()
                .set("x", x - side / 2.0)
                .set("y", y - side / 2.0)
                .set("width", side)
                .set("height", side)
                .set("fill", CELL_FILL)
                .set("fill-opacity", 0.55)
                .set("stroke", "#e6550d")
                .set("stroke-width", 0.5),
        )
    });
    let wedges = picture.images.iter().fold(Group::new(), |group, im| {
        let (x, y) = f.px(im.at);
        group.add(
            Path::new()
                .set("d", wedge_data(x, y, im.yaw, im.hfov, im.reach * f.scale))
                .set("fill", WEDGE)
                .set("fill-opacity", 0.12)
                .set("stroke", WEDGE)
                .set("stroke-opacity", 0.7)
                .set("stroke-width", 1),
        )
    });
    let wedges = wedges.set("clip-path", "url(#map-clip)");
    // The order of the images, numbered a little way along each wedge's axis.
    let numbers = picture
        .images
        .iter()
        .enumerate()
        .fold(Group::new(), |group, (i, im)| {
            let (x, y) = f.px(im.at);
            let r = 0.6 * f.scale;
            group.add(
                text(
                    (i + 1).to_string(),
                    x + r * im.yaw.cos() - 4.0,
                    y - r * im.yaw.sin() + 4.0,
                    10.0,
                )
                .set("fill", "#08306b"),
            )
        });
    let standpoints = picture
        .standpoints
        .iter()
        .enumerate()
        .fold(Group::new(), |group, (i, p)| {
            let (x, y) = f.px(*p);
            let used = picture.used.contains(&i);
            group.add(
                Circle::new()
                    .set("cx", x)
                    .set("cy", y)
                    .set("r", if used { 5 } else { 3 })
                    .set("fill", if used { USED } else { "white" })
                    .set("stroke", if used { USED } else { STANDPOINT })
                    .set("stroke-width", 1.2),
            )
        });
    let map = Group::new()
        .add(rooms(world, &f, 0.6))
        .add(doors(world, &f))
        .add(objects(world, &f))
        .add(cells)
        .add(wedges)
        .add(standpoints)
        .add(numbers);
    let mut legend = Legend::default();
    world_legend(world, &mut legend, 0.6);
    legend.add(legend_rect(CELL_FILL, "#e6550d"), "cell to cover");
    legend.add(dot(USED, USED, 5.0), "standpoint used");
    legend.add(dot("white", STANDPOINT, 3.0), "standpoint not used");
    legend.add(legend_rect("#c6dbef", WEDGE), "image (numbered in order)");
    let width_m = g.width() as f64 * g.resolution();
    let footer = Group::new().add(scale_bar(&f, width_m, 10.0, 24.0));
    compose(w, h, &picture.title, &picture.subtitle, map, legend, footer).to_string()
}

/// A legend dot.
fn dot(fill: &str, stroke: &str, r: f64) -> Group {
    Group::new().add(
        Circle::new()
            .set("cx", 12)
            .set("cy", 0)
            .set("r", r)
            .set("fill", fill)
            .set("stroke", stroke)
            .set("stroke-width", 1.2),
    )
}
