//! The legend box (only the marks a picture uses) and the scale bar.

use super::*;

/// The legend: a column of entries, each a symbol (drawn around `(12, 0)`) and its text.
#[derive(Default)]
pub(super) struct Legend {
    entries: Vec<(Group, String)>,
}

impl Legend {
    pub(super) fn add(&mut self, symbol: Group, s: impl Into<String>) {
        self.entries.push((symbol, s.into()));
    }

    const ROW: f64 = 19.0;

    pub(super) fn height(&self) -> f64 {
        28.0 + self.entries.len() as f64 * Self::ROW
    }

    /// Width of the column: the widest entry's, at least [`LEGEND_W`].
    pub(super) fn width(&self) -> f64 {
        self.entries
            .iter()
            .map(|(_, s)| 46.0 + text_width(s, Self::FONT))
            .fold(LEGEND_W, f64::max)
    }

    const FONT: f64 = 10.5;

    pub(super) fn draw(self, x: f64, y: f64) -> Group {
        let w = self.width();
        let mut g = Group::new()
            .set("id", "legend")
            .set("transform", format!("translate({x} {y})"))
            .add(
                Rectangle::new()
                    .set("x", 0)
                    .set("y", 0)
                    .set("width", w - 16.0)
                    .set("height", self.height())
                    .set("fill", "#fafafa")
                    .set("stroke", "#999"),
            )
            .add(text("Legend", 8.0, 17.0, 12.0).set("font-weight", "bold"));
        for (i, (sym, s)) in self.entries.into_iter().enumerate() {
            let cy = 28.0 + (i as f64 + 0.5) * Self::ROW;
            g = g.add(
                Group::new()
                    .set("class", "legend-entry")
                    .add(sym.set("transform", format!("translate(8 {cy})")))
                    .add(text(s, 38.0, cy + 4.0, Self::FONT)),
            );
        }
        g
    }
}

pub(super) fn legend_rect(fill: &str, stroke: &str) -> Group {
    Group::new().add(
        Rectangle::new()
            .set("x", 4)
            .set("y", -6)
            .set("width", 16)
            .set("height", 12)
            .set("fill", fill)
            .set("stroke", stroke),
    )
}

pub(super) fn legend_line(stroke: &str, width: f64) -> Group {
    Group::new().add(
        Line::new()
            .set("x1", 2)
            .set("y1", 0)
            .set("x2", 22)
            .set("y2", 0)
            .set("stroke", stroke)
            .set("stroke-width", width),
    )
}

/// The world legend entries (rooms, walls, doors, objects) of the marks `world` uses.
pub(super) fn world_legend(world: &World, legend: &mut Legend, pale: f64) {
    legend.add(
        legend_rect(&lighten(PALETTE[0], pale), "none"),
        "room (one colour each)",
    );
    legend.add(legend_rect("#222", "none"), "wall");
    if world.env.doors.iter().any(|d| d.open) {
        legend.add(legend_line("#2b8cbe", 4.0), "open door");
    }
    if world.env.doors.iter().any(|d| !d.open) {
        legend.add(legend_line("#e6550d", 4.0), "closed door");
    }
    for (role, s) in [
        (ObjectRole::Landmark, "furniture (labelled with its class)"),
        (ObjectRole::Target, "object a search may target"),
        (ObjectRole::Distractor, "distractor object"),
    ] {
        if world.env.objects.iter().any(|o| o.role == role) {
            let (fill, stroke) = object_colours(role);
            legend.add(legend_rect(fill, stroke), s);
        }
    }
}

/// The scale bar's length, metres: 2 m on maps at least 12 m wide, 1 m on smaller ones.
pub(super) fn scale_bar_m(width_m: f64) -> f64 {
    if width_m >= 12.0 {
        2.0
    } else {
        1.0
    }
}

/// The scale bar ([`scale_bar_m`]) from `(x, y)`.
pub(super) fn scale_bar(f: &Frame, width_m: f64, x: f64, y: f64) -> Group {
    let m = scale_bar_m(width_m);
    let len = m * f.scale;
    let tick = |x: f64| {
        Line::new()
            .set("x1", x)
            .set("y1", -5)
            .set("x2", x)
            .set("y2", 5)
            .set("stroke", "black")
            .set("stroke-width", 2)
    };
    Group::new()
        .set("id", "scale-bar")
        .set("transform", format!("translate({x} {y})"))
        .add(
            Line::new()
                .set("x1", 0)
                .set("y1", 0)
                .set("x2", len)
                .set("y2", 0)
                .set("stroke", "black")
                .set("stroke-width", 3),
        )
        .add(tick(0.0))
        .add(tick(len))
        .add(text(format!("{m} m"), len + 6.0, 4.0, 12.0))
}
