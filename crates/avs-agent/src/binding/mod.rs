//! The binding between the agent's memory and the planning problem: [`Binding::of`] builds
//! the problem of the world as the agent knows it (objects, facts, initial state, goal) and
//! keeps what each of its names stands for; [`Binding::action`] reads a plan step back, once,
//! into a typed [`Action`] over those values; [`check_domain`] makes sure, when the agent is
//! made, that the domain has every operator, function, variable and relation the binding and
//! the executive use. Names are made in one place ([`names`]) and read back only through the
//! binding's tables, never parsed.

mod action;
mod probs;

pub(crate) use action::{check_domain, Action, ObjArg, PlaceArg};
pub(crate) use probs::Probs;

use crate::memory::{ConeLoc, Memory, Price, Target};
use avs_concepts::RoomId;
use avs_format::knowledge::Knowledge;
use avs_map::places::dist;
use avs_plan::problem::Problem;
use petgraph::graph::NodeIndex;
use std::collections::{BTreeMap, BTreeSet, HashMap};

/// The plan names of the agent's values: the one place they are made.
pub(crate) mod names {
    use crate::memory::Target;
    use avs_concepts::RoomId;
    use petgraph::graph::NodeIndex;

    /// `place<N>` for node `N` of the place map.
    pub fn place(n: NodeIndex) -> String {
        format!("place{}", n.index())
    }
    /// `placeholder<K>` for the placeholder with stable id `K`.
    pub fn placeholder(id: usize) -> String {
        format!("placeholder{id}")
    }
    /// `room<R>` for room `R`.
    pub fn room(r: RoomId) -> String {
        format!("room{}", r.0)
    }
    /// `object<K>` for the `K`-th found object.
    pub fn object(k: usize) -> String {
        format!("object{k}")
    }
    /// The name of a target.
    pub fn target(t: Target) -> String {
        match t {
            Target::Place(n) => place(n),
            Target::Placeholder(id) => placeholder(id),
        }
    }
}

/// What a placeholder's name stands for in the problem.
#[derive(Debug, Clone, Copy)]
pub(crate) enum PhRef {
    /// An open placeholder: its id in the conceptual map.
    Current(u64),
    /// An explored one: the room it led to, if any.
    Explored(Option<RoomId>),
}

/// The problem handed to the planner and the meaning of its names.
#[derive(Debug, Clone, Default)]
pub(crate) struct Binding {
    pub problem: Problem,
    /// Position of every place and placeholder of the problem.
    pub pos: HashMap<String, [f64; 2]>,
    /// What every place and placeholder of the problem is.
    pub targets: HashMap<String, Target>,
    pub placeholders: HashMap<String, PhRef>,
    /// Position of the place each placeholder hangs off.
    pub attach: HashMap<String, [f64; 2]>,
    pub rooms: HashMap<String, RoomId>,
    pub objects: HashMap<String, usize>,
    /// The object classes that can lead to the goal: its own class and the landmark classes
    /// it (or another such class) may lie on. Assuming any other object exists cannot help a
    /// plan, so those assumptions get probability 0 and are not grounded.
    pub relevant: BTreeSet<String>,
    /// (label, room name): rooms where a search for the label made no progress and whose
    /// known map has not grown since; a search there would make none either.
    pub stalled: BTreeSet<(String, String)>,
    /// (label, room or landmark object name) → what a search there costs, metres
    /// (`skills::views::search_cost`), where it was priced.
    pub search_cost: HashMap<(String, String), Price>,
    /// Label → what a search of a room not known yet costs and the share of it its views see.
    pub typical_cost: HashMap<String, Price>,
}

/// The goal's class and, transitively, the landmark classes an object of a relevant class lies
/// on or in with a positive rate in some room category (the relations of the domain's
/// `assume-object-exists-on` and `-inside`). Only these can take part in a plan for the goal.
pub(crate) fn relevant_classes(knowledge: &Knowledge, goal: &str) -> BTreeSet<String> {
    let mut relevant = BTreeSet::from([goal.to_string()]);
    let mut todo = vec![goal.to_string()];
    while let Some(l) = todo.pop() {
        for r in &knowledge.landmark_rates {
            if r.object == l
                && r.rates.iter().any(|&x| x > 0.0)
                && relevant.insert(r.landmark.clone())
            {
                todo.push(r.landmark.clone());
            }
        }
    }
    relevant
}

impl Binding {
    /// The planning problem of the world as `mem` knows it now, for finding `goal`.
    pub fn of(mem: &Memory, knowledge: &Knowledge, goal: &str) -> Self {
        let wm = &mem.wm;
        let mut s = Binding::default();
        let mut p = Problem::new();
        for c in &knowledge.room_categories {
            p = p.object(c, "category");
        }
        // Only the classes that can lead to the goal are labels of the problem, and only the
        // objects of those classes (and what they lie on, with its class) are its objects:
        // nothing else can take part in a plan for the goal (`relevant`), and on a 30-room floor
        // the offices' desks and the sightings of other classes were most of the problem's
        // objects, each with its variables (class, location, cones per label) to ground at
        // every plan.
        s.relevant = relevant_classes(knowledge, goal);
        let in_problem: BTreeSet<usize> = mem
            .objects
            .iter()
            .enumerate()
            .filter(|(_, o)| s.relevant.contains(&o.class))
            .flat_map(|(k, o)| std::iter::once(k).chain(o.on))
            .collect();
        let labels: BTreeSet<&str> = s
            .relevant
            .iter()
            .map(String::as_str)
            .chain(in_problem.iter().map(|&k| mem.objects[k].class.as_str()))
            .collect();
        for c in &knowledge.object_classes {
            if !labels.contains(c.name.as_str()) {
                continue;
            }
            p = p.object(&c.name, "label");
            if c.landmark {
                p = p.fact(&format!("landmark({})", c.name));
            }
        }
        for (r, _) in wm.rooms() {
            let n = names::room(r);
            p = p
                .object(&n, "room")
                .init(&format!("category({n}) = unknown"));
            s.rooms.insert(n, r);
        }
        let mut in_plan: BTreeMap<NodeIndex, RoomId> = BTreeMap::new();
        for n in wm.places.graph.node_indices() {
            if mem.blocked.contains(&n) {
                continue;
            }
            let Some(r) = mem.room_for(n) else { continue };
            let name = names::place(n);
            p = p
                .object(&name, "place")
                .fact(&format!("in-room({name}, {})", names::room(r)));
            s.pos.insert(name.clone(), wm.places.graph[n].pos);
            s.targets.insert(name, Target::Place(n));
            in_plan.insert(n, r);
        }
        for (a, b, _) in wm.places.paths() {
            if in_plan.contains_key(&a) && in_plan.contains_key(&b) {
                let (na, nb) = (names::place(a), names::place(b));
                p = p
                    .fact(&format!("connected({na}, {nb})"))
                    .fact(&format!("connected({nb}, {na})"));
            }
        }
        let nearest_in_plan = |pos: [f64; 2]| {
            in_plan
                .keys()
                .min_by(|&&a, &&b| {
                    dist(wm.places.graph[a].pos, pos).total_cmp(&dist(wm.places.graph[b].pos, pos))
                })
                .copied()
        };
        let mut open: BTreeMap<RoomId, usize> = BTreeMap::new();
        let add_ph = |p: Problem,
                      name: &str,
                      pos: [f64; 2],
                      attach: Option<NodeIndex>,
                      leads: String|
         -> (Problem, Option<RoomId>) {
            let attach = attach
                .filter(|a| in_plan.contains_key(a))
                .or_else(|| nearest_in_plan(pos));
            let Some(a) = attach else { return (p, None) };
            let r = in_plan[&a];
            let pa = names::place(a);
            let p = p
                .object(name, "place")
                .fact(&format!("placeholder({name})"))
                .fact(&format!("in-room({name}, {})", names::room(r)))
                .fact(&format!("connected({pa}, {name})"))
                .fact(&format!("connected({name}, {pa})"))
                .init(&format!("leads-to({name}) = {leads}"));
            (p, Some(r))
        };
        for (k, c) in &mem.phs {
            let e = &mem.registry[*k];
            if e.explored.is_some() {
                continue;
            }
            let name = names::placeholder(e.id);
            let (q, r) = add_ph(p, &name, c.pos, Some(c.attach), "unknown".into());
            p = q;
            if let Some(a) = wm.places.graph.node_weight(c.attach) {
                s.attach.insert(name.clone(), a.pos);
            }
            if let Some(r) = r {
                *open.entry(r).or_default() += 1;
                s.pos.insert(name.clone(), c.pos);
                s.targets.insert(name.clone(), Target::Placeholder(e.id));
                s.placeholders.insert(name, PhRef::Current(c.cm_id));
            }
        }
        for e in &mem.registry {
            let Some((_, led)) = e.explored else { continue };
            let name = names::placeholder(e.id);
            let led_room = led.and_then(|n| wm.room_of(n));
            let leads = led_room.map_or("none".to_string(), names::room);
            let (q, r) = add_ph(p, &name, e.pos, None, leads);
            p = q;
            if r.is_some() {
                s.pos.insert(name.clone(), e.pos);
                s.targets.insert(name.clone(), Target::Placeholder(e.id));
                s.placeholders.insert(name, PhRef::Explored(led_room));
            }
        }
        for (r, _) in wm.rooms() {
            let n = open.get(&r).copied().unwrap_or(0).min(9);
            p = p.init(&format!("open-placeholders({}) = n{n}", names::room(r)));
        }
        // Found objects (landmarks and sightings); landmarks searched in vain for the goal are
        // left out so that the planner does not assume the goal on them again.
        for (k, o) in mem.objects.iter().enumerate() {
            if mem.exhausted.contains(&(k, goal.to_string())) || !in_problem.contains(&k) {
                continue;
            }
            let Some(r) = mem.room_for(o.place) else {
                continue;
            };
            let name = names::object(k);
            p = p
                .object(&name, "object")
                .init(&format!("class({name}) = {}", o.class))
                .init(&format!("located-in({name}) = {}", names::room(r)))
                .init(&format!("found({name}) = yes"));
            let on =
                o.on.filter(|j| {
                    in_problem.contains(j) && !mem.exhausted.contains(&(*j, goal.to_string()))
                })
                .map_or("none".to_string(), names::object);
            p = p
                .init(&format!("located-on({name}) = {on}"))
                .init(&format!("located-inside({name}) = none"));
            s.objects.insert(name, k);
        }
        for ((l, loc), (_, c)) in &mem.search_costs {
            let name = match *loc {
                ConeLoc::Room(r) => names::room(RoomId(r)),
                ConeLoc::On(k) => names::object(k),
                // A search inside a landmark is not priced (the crate docs say why).
                ConeLoc::In(_) => continue,
            };
            if let Some(c) = c {
                s.search_cost.insert((l.clone(), name), *c);
            }
        }
        for (l, c) in &mem.typical_costs {
            if let Some(c) = c {
                s.typical_cost.insert(l.clone(), *c);
            }
        }
        for ((l, r), known) in &mem.stalled {
            let name = names::room(RoomId(*r));
            if s.rooms.contains_key(&name) && mem.room_known_cells(*r) <= *known {
                s.stalled.insert((l.clone(), name));
            }
        }
        for (l, loc) in mem.cones.keys().filter(|(l, _)| s.relevant.contains(l)) {
            match *loc {
                ConeLoc::Room(r) if s.rooms.contains_key(&names::room(RoomId(r))) => {
                    p = p.init(&format!("cones-in({l}, {}) = yes", names::room(RoomId(r))));
                }
                ConeLoc::On(k) if s.objects.contains_key(&names::object(k)) => {
                    p = p.init(&format!("cones-on({l}, {}) = yes", names::object(k)));
                }
                ConeLoc::In(k) if s.objects.contains_key(&names::object(k)) => {
                    p = p.init(&format!("cones-inside({l}, {}) = yes", names::object(k)));
                }
                _ => {}
            }
        }
        // The robot is at the place it last moved to if it stands there (a door place or a
        // placeholder), else at the place map's current place.
        let target = mem.last_target.filter(|(t, q)| {
            dist(*q, mem.at) < mem.tuning.at_place && s.pos.contains_key(&names::target(*t))
        });
        let target_room = target.and_then(|(t, _)| {
            let own = match t {
                Target::Place(n) => in_plan.get(&n).copied(),
                Target::Placeholder(_) => None,
            };
            own.or_else(|| {
                let q = s.pos[&names::target(t)];
                Some(in_plan[&nearest_in_plan(q)?])
            })
        });
        match (target, target_room) {
            (Some((t, _)), Some(r)) => {
                p = p
                    .init(&format!("robot-at = {}", names::target(t)))
                    .init(&format!("robot-room = {}", names::room(r)));
            }
            _ => {
                if let Some(cur) = mem.current_place().filter(|c| in_plan.contains_key(c)) {
                    p = p
                        .init(&format!("robot-at = {}", names::place(cur)))
                        .init(&format!("robot-room = {}", names::room(in_plan[&cur])));
                }
            }
        }
        s.problem = p.goal(&format!("reported({goal}) = yes"));
        if tracing::enabled!(tracing::Level::DEBUG) {
            for (name, r) in &s.placeholders {
                tracing::debug!(placeholder = %name, pos = ?s.pos.get(name), what = ?r, "snapshot");
            }
        }
        s
    }

    /// The placeholder with stable id `id` as a plan argument: its position and the position
    /// of the place it hangs off, when the problem has them.
    pub fn placeholder_arg(&self, id: usize) -> PlaceArg {
        let name = names::placeholder(id);
        PlaceArg {
            target: Target::Placeholder(id),
            pos: self.pos.get(&name).copied(),
            attach: self.attach.get(&name).copied(),
            name,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use avs_format::knowledge::Relation;

    fn office() -> Knowledge {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../knowledge/office.yaml");
        avs_format::load_yaml(std::path::Path::new(path)).unwrap()
    }

    fn set(names: &[&str]) -> BTreeSet<String> {
        names.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn relevant_classes_are_the_goal_and_the_landmarks_it_lies_on_or_in() {
        let k = office();
        // office.yaml: cereal boxes lie on tables and counters and in shelves; staplers on
        // desks; markers on tables and desks.
        assert_eq!(
            relevant_classes(&k, "cerealbox"),
            set(&["cerealbox", "counter", "shelf", "table"])
        );
        assert_eq!(
            relevant_classes(&k, "stapler"),
            set(&["desk", "shelf", "stapler"])
        );
        assert_eq!(
            relevant_classes(&k, "whiteboardmarker"),
            set(&["desk", "table", "whiteboardmarker"])
        );
        assert_eq!(relevant_classes(&k, "table"), set(&["table"]));
    }

    #[test]
    fn the_problem_holds_only_the_classes_that_can_lead_to_the_goal_and_their_objects() {
        use crate::memory::Known;
        use crate::skills::testing;
        let (config, k) = (crate::AgentConfig::default(), office());
        let mut robot = testing::robot(testing::two_rooms(), [2.0, 2.0]);
        let mut mem = testing::memory(&config, &k, &mut robot);
        let place = mem.current_place().expect("the robot stands at a place");
        let known = |class: &str, on: Option<usize>| Known {
            class: class.into(),
            pos: avs_robot::Point3 {
                x: 2.0,
                y: 2.0,
                z: 0.75,
            },
            place,
            landmark: None,
            on,
            counted: true,
            confidence: 0.8,
        };
        // 0 a desk, 1 a table, 2 a mug on the table, 3 another desk, 4 a cereal box on it.
        mem.objects = vec![
            known("desk", None),
            known("table", None),
            known("mug", Some(1)),
            known("desk", None),
            known("cerealbox", Some(3)),
        ];
        let b = Binding::of(&mem, &k, "cerealbox");
        let of_type = |t: &str| of_type_in(&b, t);
        // The classes that lead to a cereal box, and the desk's, since a box lies on one.
        assert_eq!(
            of_type("label"),
            set(&["cerealbox", "counter", "desk", "shelf", "table"])
        );
        // The table and the cereal box, and the desk the box lies on (its location); not the
        // other desk or the mug.
        let objects: BTreeSet<String> = [1, 3, 4].into_iter().map(names::object).collect();
        assert_eq!(of_type("object"), objects);
        assert!(b.problem.init.contains(&format!(
            "located-on({}) = {}",
            names::object(4),
            names::object(3)
        )));
        // The problem is well formed: it grounds and plans.
        let planner = avs_plan::continual::ContinualPlanner::new(
            testing::domain(),
            avs_plan::continual::ContinualOptions::default(),
        );
        let f = crate::binding::probs::Probs::new(&b, &mem.wm.concepts, 0.2, 0.05);
        planner.plan(&b.problem, &f).expect("the problem plans");
        // For a stapler, desks can lead to the goal, and both are in.
        let b = Binding::of(&mem, &k, "stapler");
        assert!(of_type_in(&b, "object").contains(&names::object(0)));
        assert!(!of_type_in(&b, "object").contains(&names::object(2)));
    }

    /// The domain's search costs and success of a room search come from the prices the
    /// memory holds: the room's own, a room not known yet's for a hypothesised room, and the
    /// flat ones where nothing is priced.
    #[test]
    fn searches_cost_what_they_were_priced_and_succeed_with_the_share_they_see() {
        use crate::memory::Price;
        use crate::skills::testing;
        use avs_plan::problem::Functions;
        let (config, k) = (crate::AgentConfig::default(), office());
        let mut robot = testing::robot(testing::two_rooms(), [2.0, 2.0]);
        let mut mem = testing::memory(&config, &k, &mut robot);
        let room = mem.current_room().expect("a room");
        let f = |b: &Binding, name: &str, args: &[&str]| {
            crate::binding::probs::Probs::new(b, &mem.wm.concepts, 0.2, 0.05)
                .value(name, args)
                .expect("the agent supplies it")
        };
        let r = names::room(room);
        let b = Binding::of(&mem, &k, "cerealbox");
        assert_eq!(f(&b, "search-cost-in", &["cerealbox", &r]), 20.0);
        assert_eq!(f(&b, "search-cost-on", &["cerealbox", "object0"]), 5.0);
        assert!((f(&b, "p-detect-in", &["cerealbox", &r]) - 0.8).abs() < 1e-12);
        let price = Price {
            metres: 33.0,
            share: 0.5,
        };
        mem.search_costs.insert(
            ("cerealbox".into(), ConeLoc::Room(room.0)),
            ((1, 0, 0), Some(price)),
        );
        let typical = Price {
            metres: 17.0,
            share: 0.75,
        };
        mem.typical_costs.insert("cerealbox".into(), Some(typical));
        let b = Binding::of(&mem, &k, "cerealbox");
        assert_eq!(f(&b, "search-cost-in", &["cerealbox", &r]), 33.0);
        assert_eq!(f(&b, "search-cost-in", &["cerealbox", "new-room1"]), 17.0);
        assert!((f(&b, "p-detect-in", &["cerealbox", &r]) - 0.4).abs() < 1e-12);
        assert!((f(&b, "p-detect-in", &["cerealbox", "new-room1"]) - 0.6).abs() < 1e-12);
        // A room no view sees yet is priced as one not known yet.
        mem.search_costs.insert(
            ("cerealbox".into(), ConeLoc::Room(room.0)),
            ((1, 0, 0), None),
        );
        let b = Binding::of(&mem, &k, "cerealbox");
        assert_eq!(f(&b, "search-cost-in", &["cerealbox", &r]), 17.0);
        assert!((f(&b, "p-detect-in", &["cerealbox", &r]) - 0.6).abs() < 1e-12);
    }

    /// The names of the problem's objects of type `t`.
    fn of_type_in(b: &Binding, t: &str) -> BTreeSet<String> {
        b.problem
            .objects
            .iter()
            .filter(|(_, ty)| ty == t)
            .map(|(n, _)| n.clone())
            .collect()
    }

    #[test]
    fn relevance_follows_landmarks_on_landmarks() {
        let mut k = office();
        // Made up: cereal boxes only on mugs; then the landmarks mugs lie on become relevant
        // (table and desk in office.yaml), but not counters, where mugs have rate 0 here.
        k.landmark_rates.retain(|r| r.object != "cerealbox");
        k.landmark_rates.push(avs_format::knowledge::LandmarkRate {
            object: "cerealbox".into(),
            relation: Relation::On,
            landmark: "mug".into(),
            rates: vec![0.0, 0.1, 0.0],
        });
        k.landmark_rates.push(avs_format::knowledge::LandmarkRate {
            object: "mug".into(),
            relation: Relation::On,
            landmark: "counter".into(),
            rates: vec![0.0, 0.0, 0.0],
        });
        assert_eq!(
            relevant_classes(&k, "cerealbox"),
            set(&["cerealbox", "desk", "mug", "table"])
        );
    }
}
