//! `avs segment`: segment a complete map into rooms by door hypotheses, optionally score the
//! result against ground truth and draw it as SVG.
//!
//! The map is either a ROS map_server descriptor (YAML naming a PGM/PNG image) or an avs
//! environment file (`kind: environment`, with an ASCII or image map); the file's content
//! decides, not its name. An environment is loaded as every other command loads it
//! ([`avs_sim::World::load`]: `avs validate`'s checks, then the world's grids), and what is
//! segmented is its [`avs_sim::World::walls`] grid: the map's walls with closed doors drawn
//! shut, without furniture footprints (the building, as a complete map of it would show it).
//!
//! Ground truth: `--truth IMAGE` (white rooms separated by black lines) for any map. An
//! environment with `rooms` is scored against them without an image: the rooms rasterised the
//! way the simulator does ([`avs_sim::World::room_of_cell`]: polygons by containment, seeds by
//! flood fill that stops at door openings, door cells given to a neighbouring room); an
//! environment without rooms is not scored, and the output says so.

use anyhow::Context;
use avs_format::FileKind;
use avs_map::grid::OccupancyGrid;
use avs_map::metrics::{load_truth_image, score, SegmentationScore};
use avs_map::segment::{segment_rooms, SegmentParams, Segmentation};
use avs_sim::{SimError, World};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// Flags.
#[derive(clap::Args)]
pub struct Args {
    /// The complete map: a ROS map_server descriptor (YAML), or an avs environment file
    /// (`kind: environment`), whose rooms are the ground truth.
    pub map: PathBuf,
    /// Ground-truth segmentation image (white rooms separated by black lines) to score against
    /// (for an environment, instead of its rooms).
    #[arg(long)]
    pub truth: Option<PathBuf>,
    /// Write the segmentation as SVG to this file.
    #[arg(long)]
    pub svg: Option<PathBuf>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
    /// Narrowest door opening in metres.
    #[arg(long, default_value_t = 0.7)]
    pub min_door_width: f64,
    /// Widest door opening in metres.
    #[arg(long, default_value_t = 1.2)]
    pub max_door_width: f64,
    /// Smallest room in square metres.
    #[arg(long, default_value_t = 1.0)]
    pub min_room_area: f64,
}

/// A map to segment, with the ground truth it carries (an environment's rooms).
struct MapInput {
    /// `environment` or `map_server`: which reader read the file.
    format: &'static str,
    grid: OccupancyGrid,
    /// Truth room of every cell (`OccupancyGrid::index` order, 1-based, 0 = none): an
    /// environment's rooms; `None` for a map_server map and an environment without rooms.
    rooms: Option<Vec<u32>>,
}

/// Ground truth to score against.
struct Truth {
    labels: Vec<u32>,
    /// Where it came from, for the output: `image` or `environment`.
    source: &'static str,
}

/// Read the map: an avs environment when the YAML has `kind: environment`, a ROS map_server
/// descriptor when it has no `kind`; any other kind is an error naming the file.
fn read_map(path: &Path) -> anyhow::Result<MapInput> {
    let name = path.display().to_string();
    let text = avs_format::read_text(path)?;
    /// Only the `kind` field, whatever else the file holds.
    #[derive(serde::Deserialize)]
    struct Probe {
        kind: Option<serde_yaml::Value>,
    }
    // YAML that is not a mapping at all is left to the map_server reader, which says what it
    // expects with the line and column.
    let has_kind = avs_format::load_yaml_str::<Probe>(&name, &text)
        .map(|p| p.kind.is_some())
        .unwrap_or(false);
    if !has_kind {
        // The reader's errors name the file (and line); the context says what else is read.
        let grid = OccupancyGrid::from_map_server_yaml(path).context(
            "expected a ROS map_server descriptor (image, resolution, origin, occupied_thresh, \
             free_thresh) or an avs environment (`kind: environment`)",
        )?;
        return Ok(MapInput {
            format: "map_server",
            grid,
            rooms: None,
        });
    }
    match avs_format::read_kind(&name, &text)? {
        FileKind::Environment => {}
        other => anyhow::bail!(
            "{name}: kind: {}; expected an environment (`kind: environment`) or a ROS \
             map_server descriptor (image, resolution, origin)",
            other.name()
        ),
    }
    // The checks' diagnostics name the file, line and field; other errors get the file's name.
    let world = World::load(path).map_err(|e| match e {
        SimError::Checks(_) => anyhow::Error::new(e),
        other => anyhow::anyhow!("{name}: {other}"),
    })?;
    let rooms = (!world.env.rooms.is_empty()).then(|| {
        world
            .room_of_cell
            .iter()
            .map(|r| r.map_or(0, |i| i as u32 + 1))
            .collect()
    });
    Ok(MapInput {
        format: "environment",
        grid: world.walls,
        rooms,
    })
}

/// Run the subcommand.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let MapInput {
        format,
        grid,
        rooms,
    } = read_map(&args.map)?;
    let mut params = SegmentParams::default();
    params.doors.min_width = args.min_door_width;
    params.doors.max_width = args.max_door_width;
    params.min_room_area = args.min_room_area;
    let start = Instant::now();
    let seg = segment_rooms(&grid, &params).context("segmenting")?;
    let ms = start.elapsed().as_secs_f64() * 1e3;

    let truth: Option<Truth> = match (&args.truth, rooms) {
        (Some(path), _) => {
            let truth = load_truth_image(path)?;
            if (truth.width, truth.height) != (grid.width(), grid.height()) {
                anyhow::bail!(
                    "{}: ground truth is {}×{} px but the map {} is {}×{} cells; expected the same size",
                    path.display(),
                    truth.width,
                    truth.height,
                    args.map.display(),
                    grid.width(),
                    grid.height()
                );
            }
            Some(Truth {
                labels: truth.labels,
                source: "image",
            })
        }
        (None, Some(labels)) => Some(Truth {
            labels,
            source: "environment",
        }),
        (None, None) => None,
    };
    let scored: Option<SegmentationScore> = match &truth {
        Some(t) => Some(score(&seg.labels, &t.labels)?),
        None => None,
    };
    // Why there is no score, when the map could have had one.
    let unscored = (scored.is_none() && format == "environment")
        .then_some("the environment has no rooms: not scored");

    if let Some(path) = &args.svg {
        std::fs::write(path, svg(&grid, &seg))
            .with_context(|| format!("writing {}", path.display()))?;
    }

    if args.json {
        let s = scored.as_ref();
        let out = serde_json::json!({
            "map": args.map.display().to_string(),
            "format": format,
            "width": grid.width(),
            "height": grid.height(),
            "rooms": seg.rooms,
            "doors": seg.doors,
            "truth": truth.as_ref().map(|t| t.source),
            "truth_rooms": s.map(|s| s.truth_rooms),
            "precision_per_room": s.map(|s| s.precision_per_room),
            "recall_per_room": s.map(|s| s.recall_per_room),
            "precision_pixel": s.map(|s| s.precision_pixel),
            "recall_pixel": s.map(|s| s.recall_pixel),
            "mcc": s.map(|s| s.mcc),
            "note": unscored,
            "ms": ms,
        });
        println!("{}", serde_json::to_string(&out)?);
    } else {
        println!(
            "{}: {} rooms, {} doors ({:.1} ms)",
            args.map.display(),
            seg.rooms,
            seg.doors.len(),
            ms
        );
        if let (Some(s), Some(t)) = (scored, &truth) {
            let from = match t.source {
                "environment" => " (the environment's rooms)",
                _ => "",
            };
            println!(
                "truth rooms {}{from}; per room: precision {:.3}, recall {:.3}; per pixel: precision {:.3}, recall {:.3}; MCC {:.3}",
                s.truth_rooms,
                s.precision_per_room,
                s.recall_per_room,
                s.precision_pixel,
                s.recall_pixel,
                s.mcc
            );
        }
        if let Some(note) = unscored {
            println!("note: {note}");
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// A distinct colour per room (golden-ratio hue steps, fixed saturation and value).
fn colour(label: u32) -> String {
    let hue = (f64::from(label) * 0.618_033_988_75).fract() * 6.0;
    let (s, v) = (0.55, 0.92);
    let c = v * s;
    let x = c * (1.0 - ((hue % 2.0) - 1.0).abs());
    let (r, g, b) = match hue as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let m = v - c;
    let to = |u: f64| ((u + m) * 255.0).round() as u8;
    format!("#{:02x}{:02x}{:02x}", to(r), to(g), to(b))
}

/// The segmentation as SVG: one unit per cell, top row first; one rect per horizontal run of
/// equal room labels; doors as lines between their jambs.
fn svg(grid: &OccupancyGrid, seg: &Segmentation) -> String {
    let (w, h) = (grid.width(), grid.height());
    let mut out = String::new();
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" shape-rendering="crispEdges">"#
    );
    let _ = writeln!(
        out,
        r##"<rect x="0" y="0" width="{w}" height="{h}" fill="#333333"/>"##
    );
    for row in 0..h {
        let y = h - 1 - row;
        let mut col = 0;
        while col < w {
            let l = seg.labels[grid.index(col, row)];
            let mut end = col + 1;
            while end < w && seg.labels[grid.index(end, row)] == l {
                end += 1;
            }
            if l != 0 {
                let _ = writeln!(
                    out,
                    r#"<rect x="{col}" y="{y}" width="{}" height="1" fill="{}"/>"#,
                    end - col,
                    colour(l)
                );
            }
            col = end;
        }
    }
    let (ox, oy) = (grid.origin()[0], grid.origin()[1]);
    let r = grid.resolution();
    for d in &seg.doors {
        let p = |q: [f64; 2]| ((q[0] - ox) / r, h as f64 - (q[1] - oy) / r);
        let (a, b) = (p(d.jambs[0]), p(d.jambs[1]));
        let _ = writeln!(
            out,
            r#"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="red" stroke-width="2"/>"#,
            a.0, a.1, b.0, b.1
        );
    }
    out.push_str("</svg>\n");
    out
}
