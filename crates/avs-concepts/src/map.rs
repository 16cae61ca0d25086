//! The conceptual map: room-category variables joined by connectivity potentials, evidence
//! from place properties and object counts, Poisson object priors, placeholder predictions.

use crate::factor::{Factor, FactorGraph};
use crate::ids::{LandmarkId, Location, PlaceId, Placeholder, PlaceholderId, RoomId};
use crate::model::Model;
use crate::pairwise::{MapBpOptions, PairwiseMrf};
use crate::placeholder::{hypothesis_probabilities, Hypotheses};
use crate::ConceptError;
use avs_format::knowledge::{Knowledge, Relation};
use std::collections::{BTreeMap, BTreeSet, HashMap};

#[derive(Debug, Clone, Default)]
struct PlaceObs {
    /// (property, soft evidence over its values)
    properties: Vec<(usize, Vec<f64>)>,
    /// The object counts made from this place.
    counts: Vec<CountObs>,
}

/// One look's count of instances of a class not counted before (see
/// [`ConceptualMap::observe_objects`]).
#[derive(Debug, Clone, Copy)]
struct CountObs {
    /// When it was made, in the map's count order: the looks before it thin its rate.
    seq: u64,
    class: usize,
    /// Instances first counted in this look.
    new: u32,
    /// The looked-at share of the room.
    coverage: f64,
}

#[derive(Debug, Clone, Default)]
struct RoomState {
    places: BTreeMap<PlaceId, PlaceObs>,
    /// Remaining (unsearched) share of the room's own area per class, Π(1 − q).
    searched: BTreeMap<usize, f64>,
    landmarks: BTreeSet<LandmarkId>,
}

#[derive(Debug, Clone)]
struct LandmarkState {
    room: RoomId,
    class: usize,
    /// Remaining share per (relation, object class).
    searched: BTreeMap<(Relation, usize), f64>,
}

/// Statistics of the last inference run.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct InferenceStats {
    /// BP sweeps over the rooms whose messages needed updating.
    pub iterations: usize,
    /// Messages recomputed.
    pub updates: usize,
    /// Whether BP converged.
    pub converged: bool,
    /// Last belief change.
    pub max_diff: f64,
}

/// The conceptual map (Aydemir et al. 2011, §II-B.4 and §III): an event-driven chain graph over
/// room categories, kept up to date by warm-started loopy BP after every event.
///
/// ```
/// use avs_concepts::{ConceptualMap, PlaceId, RoomId};
/// let k: avs_format::knowledge::Knowledge = avs_format::load_yaml_str("k.yaml", r#"
/// kind: knowledge
/// name: tiny
/// room_categories: [corridor, kitchen]
/// object_classes:
///   - { name: counter, size: [2, 0.6, 0.9], detection_range: [0.5, 5], recognition_range: [0.5, 4], landmark: true }
/// object_rates: { counter: [0.01, 1.2] }
/// "#).unwrap();
/// let mut map = ConceptualMap::new("k.yaml", &k).unwrap();
/// map.add_room(RoomId(1)).unwrap();
/// let before = map.p_category(RoomId(1), "kitchen").unwrap();
/// map.observe_objects(RoomId(1), PlaceId(7), "counter", 1, 1.0).unwrap();
/// assert!(map.p_category(RoomId(1), "kitchen").unwrap() > before);
/// ```
#[derive(Debug, Clone)]
pub struct ConceptualMap {
    model: Model,
    rooms: BTreeMap<RoomId, RoomState>,
    adjacency: BTreeSet<(RoomId, RoomId)>,
    landmarks: BTreeMap<LandmarkId, LandmarkState>,
    placeholders: BTreeMap<PlaceholderId, Placeholder>,
    next_landmark: u64,
    /// Sequence number of the next count observation.
    next_count: u64,
    opts: MapBpOptions,
    mrf: PairwiseMrf,
    node_ids: Vec<RoomId>,
    node_of: HashMap<RoomId, usize>,
    stats: InferenceStats,
    /// Whether a room's rate counts the landmarks not found yet ([`Self::set_unfound_landmarks`]).
    unfound_landmarks: bool,
    /// Exact marginals by node, used when BP did not converge and the graph is small.
    exact_fallback: Option<Vec<Vec<f64>>>,
}

/// Largest junction tree (table entries) the map uses as a fallback when BP does not converge.
pub const EXACT_FALLBACK_ENTRIES: usize = 1 << 20;

fn ordered(a: RoomId, b: RoomId) -> (RoomId, RoomId) {
    if a <= b {
        (a, b)
    } else {
        (b, a)
    }
}

fn check_prob(what: &'static str, v: f64) -> Result<(), ConceptError> {
    if (0.0..=1.0).contains(&v) {
        Ok(())
    } else {
        Err(ConceptError::BadNumber {
            what,
            value: v,
            expected: "a probability in [0, 1]",
        })
    }
}

/// ln Poisson(n; λ) (eq. 1), −∞ when λ = 0 < n.
fn ln_poisson(n: u32, lambda: f64) -> f64 {
    if lambda <= 0.0 {
        return if n == 0 { 0.0 } else { f64::NEG_INFINITY };
    }
    let lnfact: f64 = (1..=n).map(|i| (i as f64).ln()).sum();
    n as f64 * lambda.ln() - lambda - lnfact
}

impl ConceptualMap {
    /// An empty map over the knowledge `k` (checked as `avs validate` does; `file` names it).
    pub fn new(file: &str, k: &Knowledge) -> Result<Self, ConceptError> {
        Ok(Self::from_model(Model::from_knowledge(file, k)?))
    }

    /// An empty map over a dense model (built and checked by [`Model::from_knowledge`]).
    fn from_model(model: Model) -> Self {
        ConceptualMap {
            model,
            rooms: BTreeMap::new(),
            adjacency: BTreeSet::new(),
            landmarks: BTreeMap::new(),
            placeholders: BTreeMap::new(),
            next_landmark: 0,
            next_count: 0,
            opts: MapBpOptions::default(),
            mrf: PairwiseMrf::default(),
            node_ids: Vec::new(),
            node_of: HashMap::new(),
            stats: InferenceStats::default(),
            exact_fallback: None,
            unfound_landmarks: false,
        }
    }

    /// Count the landmarks not found yet in a room's rate of an object (and in the rooms
    /// behind placeholders, [`Model::unseen_room_rates`]): §III-A's whole hierarchy. Off by
    /// default: a room's rate is its own plus its known landmarks' (see the crate docs,
    /// *P(ObjectAt L)*, for what each gives and why the default is off for now).
    pub fn set_unfound_landmarks(&mut self, on: bool) {
        self.unfound_landmarks = on;
    }

    /// Whether a room's rate counts the landmarks not found yet.
    pub fn unfound_landmarks(&self) -> bool {
        self.unfound_landmarks
    }

    /// The dense knowledge model.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// Change the BP options (and re-run inference).
    pub fn set_bp_options(&mut self, opts: MapBpOptions) -> Result<(), ConceptError> {
        if !(0.0..1.0).contains(&opts.damping) || opts.tol.is_nan() || opts.tol < 0.0 {
            return Err(ConceptError::BadNumber {
                what: "BP damping / tolerance",
                value: opts.damping,
                expected: "damping in [0, 1) and tol >= 0",
            });
        }
        self.opts = opts;
        self.infer()
    }

    /// Forget the BP messages, so the next inference starts cold (benchmarks, debugging).
    pub fn reset_messages(&mut self) {
        self.mrf = PairwiseMrf::default();
        self.node_ids.clear();
        self.node_of.clear();
        self.exact_fallback = None;
    }

    /// Whether the current beliefs come from exact inference because BP did not converge.
    pub fn uses_exact_fallback(&self) -> bool {
        self.exact_fallback.is_some()
    }

    /// Statistics of the last BP run.
    pub fn stats(&self) -> InferenceStats {
        self.stats
    }

    /// The rooms, in id order.
    pub fn rooms(&self) -> impl Iterator<Item = RoomId> + '_ {
        self.rooms.keys().copied()
    }

    fn room(&self, r: RoomId) -> Result<&RoomState, ConceptError> {
        self.rooms.get(&r).ok_or(ConceptError::UnknownRoom(r.0))
    }
    fn room_mut(&mut self, r: RoomId) -> Result<&mut RoomState, ConceptError> {
        self.rooms.get_mut(&r).ok_or(ConceptError::UnknownRoom(r.0))
    }

    // ---------------------------------------------------------------- events

    /// Add a room (no observations yet).
    pub fn add_room(&mut self, r: RoomId) -> Result<(), ConceptError> {
        if self.rooms.contains_key(&r) {
            return Err(ConceptError::Duplicate("room", r.0));
        }
        self.rooms.insert(r, RoomState::default());
        self.infer()
    }

    /// Remove a room with its doors, landmarks and placeholders.
    pub fn remove_room(&mut self, r: RoomId) -> Result<(), ConceptError> {
        let st = self
            .rooms
            .remove(&r)
            .ok_or(ConceptError::UnknownRoom(r.0))?;
        for l in st.landmarks {
            self.landmarks.remove(&l);
        }
        self.adjacency.retain(|(a, b)| *a != r && *b != r);
        self.placeholders.retain(|_, p| p.room != r);
        self.infer()
    }

    /// Merge room `gone` into room `keep` (a door hypothesis was dropped): places, landmarks,
    /// doors and placeholders move to `keep`; the unsearched shares are averaged.
    pub fn merge_rooms(&mut self, keep: RoomId, gone: RoomId) -> Result<(), ConceptError> {
        self.room(keep)?;
        if keep == gone {
            return Ok(());
        }
        let g = self
            .rooms
            .remove(&gone)
            .ok_or(ConceptError::UnknownRoom(gone.0))?;
        let k = self.rooms.get_mut(&keep).expect("checked");
        for (p, o) in g.places {
            let e = k.places.entry(p).or_default();
            e.properties.extend(o.properties);
            e.counts.extend(o.counts);
        }
        let classes: BTreeSet<usize> = k
            .searched
            .keys()
            .chain(g.searched.keys())
            .copied()
            .collect();
        for c in classes {
            let a = k.searched.get(&c).copied().unwrap_or(1.0);
            let b = g.searched.get(&c).copied().unwrap_or(1.0);
            k.searched.insert(c, 0.5 * (a + b));
        }
        k.landmarks.extend(g.landmarks.iter().copied());
        for l in g.landmarks {
            if let Some(ls) = self.landmarks.get_mut(&l) {
                ls.room = keep;
            }
        }
        let adj: Vec<(RoomId, RoomId)> = self.adjacency.iter().copied().collect();
        self.adjacency.clear();
        for (a, b) in adj {
            let a = if a == gone { keep } else { a };
            let b = if b == gone { keep } else { b };
            if a != b {
                self.adjacency.insert(ordered(a, b));
            }
        }
        for p in self.placeholders.values_mut() {
            if p.room == gone {
                p.room = keep;
            }
        }
        self.infer()
    }

    /// Split room `from`: the listed places (with their observations) and landmarks move to the
    /// new room `new`, which is joined to `from` by a door. Searched shares are copied.
    pub fn split_room(
        &mut self,
        from: RoomId,
        new: RoomId,
        places: &[PlaceId],
        landmarks: &[LandmarkId],
    ) -> Result<(), ConceptError> {
        if self.rooms.contains_key(&new) {
            return Err(ConceptError::Duplicate("room", new.0));
        }
        let f = self.room_mut(from)?;
        let mut st = RoomState {
            searched: f.searched.clone(),
            ..RoomState::default()
        };
        for p in places {
            if let Some(o) = f.places.remove(p) {
                st.places.insert(*p, o);
            }
        }
        for l in landmarks {
            if f.landmarks.remove(l) {
                st.landmarks.insert(*l);
            }
        }
        for l in &st.landmarks {
            if let Some(ls) = self.landmarks.get_mut(l) {
                ls.room = new;
            }
        }
        self.rooms.insert(new, st);
        self.adjacency.insert(ordered(from, new));
        self.infer()
    }

    /// Join two rooms by a door.
    pub fn add_adjacency(&mut self, a: RoomId, b: RoomId) -> Result<(), ConceptError> {
        self.room(a)?;
        self.room(b)?;
        if a == b {
            return Err(ConceptError::BadNumber {
                what: "door between a room and itself",
                value: a.0 as f64,
                expected: "two different rooms",
            });
        }
        if self.adjacency.insert(ordered(a, b)) {
            self.infer()
        } else {
            Ok(())
        }
    }

    /// Remove the door between two rooms.
    pub fn remove_adjacency(&mut self, a: RoomId, b: RoomId) -> Result<(), ConceptError> {
        if self.adjacency.remove(&ordered(a, b)) {
            self.infer()
        } else {
            Ok(())
        }
    }

    /// Add or replace a placeholder.
    pub fn set_placeholder(
        &mut self,
        id: PlaceholderId,
        p: Placeholder,
    ) -> Result<(), ConceptError> {
        self.room(p.room)?;
        if !(p.open_area_m2.is_finite() && p.open_area_m2 >= 0.0) {
            return Err(ConceptError::BadNumber {
                what: "placeholder open area (m²)",
                value: p.open_area_m2,
                expected: "a finite area >= 0",
            });
        }
        if let Some(d) = p.door_distance_m {
            if !(d.is_finite() && d >= 0.0) {
                return Err(ConceptError::BadNumber {
                    what: "placeholder door distance (m)",
                    value: d,
                    expected: "a finite distance >= 0",
                });
            }
        }
        self.placeholders.insert(id, p);
        Ok(())
    }

    /// Remove a placeholder (it was explored).
    pub fn remove_placeholder(&mut self, id: PlaceholderId) -> Result<(), ConceptError> {
        self.placeholders
            .remove(&id)
            .map(|_| ())
            .ok_or(ConceptError::UnknownPlaceholder(id.0))
    }

    /// A place property classifier reported `value` for `property` at `place` of `room`.
    pub fn observe_property(
        &mut self,
        room: RoomId,
        place: PlaceId,
        property: &str,
        value: &str,
    ) -> Result<(), ConceptError> {
        let p = self.model.property(property)?;
        let pm = &self.model.properties[p];
        let v = pm
            .values
            .iter()
            .position(|x| x == value)
            .ok_or_else(|| ConceptError::Unknown {
                what: "property value",
                name: value.into(),
                known: pm.values.join(", "),
            })?;
        let mut soft = vec![0.0; pm.values.len()];
        soft[v] = 1.0;
        self.observe_property_soft(room, place, property, &soft)
    }

    /// Soft evidence for a place property: `likelihood[v]` ∝ P(classifier output | value v).
    /// The room's factor gains `Σ_v P(v | category) · likelihood[v]`.
    pub fn observe_property_soft(
        &mut self,
        room: RoomId,
        place: PlaceId,
        property: &str,
        likelihood: &[f64],
    ) -> Result<(), ConceptError> {
        let p = self.model.property(property)?;
        let nv = self.model.properties[p].values.len();
        if likelihood.len() != nv
            || likelihood.iter().any(|x| !x.is_finite() || *x < 0.0)
            || likelihood.iter().sum::<f64>() <= 0.0
        {
            return Err(ConceptError::BadNumber {
                what: "property likelihood",
                value: likelihood.len() as f64,
                expected: "one finite non-negative number per property value, not all zero",
            });
        }
        self.room_mut(room)?
            .places
            .entry(place)
            .or_default()
            .properties
            .push((p, likelihood.to_vec()));
        self.refresh_room(room)
    }

    /// From `place`, the robot counted `count` instances of `class` in `room` that it had not
    /// counted before, looking at a share `coverage` ∈ (0, 1] of the room. Under category k the
    /// count is Poisson with rate `s · (p_d · λ_{k,class} · U + λ_fp)` (thinning of eq. 1 over
    /// the looked-at cells, plus spurious counts), where `U = Π (1 − s_j · p_d)` over the
    /// room's earlier counts of the class: only instances every earlier look missed can be new
    /// (see the crate docs, *Object counts*).
    pub fn observe_objects(
        &mut self,
        room: RoomId,
        place: PlaceId,
        class: &str,
        count: u32,
        coverage: f64,
    ) -> Result<(), ConceptError> {
        let c = self.model.class(class)?;
        if !(coverage > 0.0 && coverage <= 1.0) {
            return Err(ConceptError::BadNumber {
                what: "coverage",
                value: coverage,
                expected: "a share of the room in (0, 1]",
            });
        }
        let seq = self.next_count;
        self.room_mut(room)?
            .places
            .entry(place)
            .or_default()
            .counts
            .push(CountObs {
                seq,
                class: c,
                new: count,
                coverage,
            });
        self.next_count += 1;
        self.refresh_room(room)
    }

    /// A landmark instance of `class` (e.g. a table) was found in `room`; it becomes a
    /// location for the in/on relations. Returns its id.
    pub fn add_landmark(&mut self, room: RoomId, class: &str) -> Result<LandmarkId, ConceptError> {
        let c = self.model.class(class)?;
        if !self.model.landmark[c] {
            return Err(ConceptError::NotALandmark(class.into()));
        }
        let id = LandmarkId(self.next_landmark);
        self.next_landmark += 1;
        self.room_mut(room)?.landmarks.insert(id);
        self.landmarks.insert(
            id,
            LandmarkState {
                room,
                class: c,
                searched: BTreeMap::new(),
            },
        );

        Ok(id)
    }

    /// `location` was searched for `class` without success, with detection probability `q`.
    /// The rates are thinned, λ ← (1 − q) λ (a Poisson process thinned by detection), and the
    /// failure is evidence about the room's category: likelihood exp(−q λ_k) under category k.
    /// Searching a room searches every landmark location in it too.
    pub fn mark_searched(
        &mut self,
        location: Location,
        class: &str,
        q: f64,
    ) -> Result<(), ConceptError> {
        let c = self.model.class(class)?;
        check_prob("detection probability q", q)?;
        let room = match location {
            Location::Room(r) => r,
            Location::Landmark(l, _) => {
                self.landmarks
                    .get(&l)
                    .ok_or(ConceptError::UnknownLandmark(l.0))?
                    .room
            }
        };
        match location {
            Location::Room(r) => {
                let st = self.room_mut(r)?;
                *st.searched.entry(c).or_insert(1.0) *= 1.0 - q;
                let lms: Vec<LandmarkId> = st.landmarks.iter().copied().collect();
                for l in lms {
                    let ls = self.landmarks.get_mut(&l).expect("consistent");
                    for rel in [Relation::In, Relation::On] {
                        *ls.searched.entry((rel, c)).or_insert(1.0) *= 1.0 - q;
                    }
                }
            }
            Location::Landmark(l, rel) => {
                let ls = self
                    .landmarks
                    .get_mut(&l)
                    .ok_or(ConceptError::UnknownLandmark(l.0))?;
                *ls.searched.entry((rel, c)).or_insert(1.0) *= 1.0 - q;
            }
        }
        self.refresh_room(room)
    }

    // ---------------------------------------------------------------- inference

    /// ln of the room's unary factor (prior × property likelihoods × count likelihoods ×
    /// failed-search likelihoods), per category.
    fn ln_unary(&self, st: &RoomState) -> Vec<f64> {
        let m = &self.model;
        let kc = m.num_categories();
        let mut u: Vec<f64> = m.prior.iter().map(|p| p.ln()).collect();
        for o in st.places.values() {
            for (p, lik) in &o.properties {
                let t = &m.properties[*p].given_category;
                for (k, uk) in u.iter_mut().enumerate() {
                    let s: f64 = t[k].iter().zip(lik).map(|(a, b)| a * b).sum();
                    *uk += s.ln();
                }
            }
        }
        // Object counts, per class in the order they were made: look i's new instances are
        // those it found and every earlier look missed.
        let mut counts: Vec<&CountObs> = st.places.values().flat_map(|o| &o.counts).collect();
        counts.sort_by_key(|o| (o.class, o.seq));
        let mut unseen = 1.0; // Π (1 − s_j p_d) over the class's earlier looks
        for (i, o) in counts.iter().enumerate() {
            if i == 0 || counts[i - 1].class != o.class {
                unseen = 1.0;
            }
            let (c, cov) = (o.class, o.coverage);
            let term: Vec<f64> = (0..kc)
                .map(|k| {
                    ln_poisson(
                        o.new,
                        cov * (m.count_detection * m.room_rates[c][k] * unseen
                            + m.count_false_positive),
                    )
                })
                .collect();
            unseen *= 1.0 - cov * m.count_detection;
            if term.iter().all(|x| *x == f64::NEG_INFINITY) {
                tracing::warn!(class = %m.classes[c], n = o.new, "count impossible under every category; ignored");
                continue;
            }
            u.iter_mut().zip(term).for_each(|(a, b)| *a += b);
        }
        // Failed searches: exp(−λ_k (1 − t)) for each searched location.
        for (&c, &t) in &st.searched {
            for (k, uk) in u.iter_mut().enumerate() {
                *uk -= m.room_rates[c][k] * (1.0 - t);
            }
        }
        for l in &st.landmarks {
            let ls = &self.landmarks[l];
            for (&(rel, c), &t) in &ls.searched {
                let rate = m.landmark_rate(c, rel, ls.class);
                for (k, uk) in u.iter_mut().enumerate() {
                    *uk -= rate[k] * (1.0 - t);
                }
            }
        }
        u
    }

    fn normalized_unary(&self, r: RoomId) -> Result<Vec<f64>, ConceptError> {
        let lu = self.ln_unary(&self.rooms[&r]);
        let mx = lu.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        if !mx.is_finite() {
            return Err(ConceptError::Graph(crate::GraphError::Inconsistent(
                format!(
                    "the observations of room {} are impossible under every category",
                    r.0
                ),
            )));
        }
        Ok(lu.iter().map(|x| (x - mx).exp()).collect())
    }

    fn phi_row_major(&self) -> Vec<f64> {
        self.model.connectivity.iter().flatten().copied().collect()
    }

    /// Rebuild the chain graph (after a structural event) and re-run BP, warm-started from
    /// the previous messages of every door that still exists.
    pub fn infer(&mut self) -> Result<(), ConceptError> {
        let kc = self.model.num_categories();
        let ids: Vec<RoomId> = self.rooms.keys().copied().collect();
        let node_of: HashMap<RoomId, usize> =
            ids.iter().enumerate().map(|(i, r)| (*r, i)).collect();
        let mut unary = Vec::with_capacity(ids.len() * kc);
        for r in &ids {
            unary.extend(self.normalized_unary(*r)?);
        }
        let edges: Vec<(usize, usize)> = self
            .adjacency
            .iter()
            .map(|(a, b)| (node_of[a], node_of[b]))
            .collect();
        let mut old: HashMap<(RoomId, RoomId), Vec<f64>> = HashMap::new();
        for (e, &(i, j)) in self.mrf.edges().iter().enumerate() {
            let (ri, rj) = (self.node_ids[i], self.node_ids[j]);
            old.insert((ri, rj), self.mrf.message(e, true).to_vec());
            old.insert((rj, ri), self.mrf.message(e, false).to_vec());
        }
        let mrf = PairwiseMrf::new(kc, self.phi_row_major(), unary, edges, |i, j| {
            old.remove(&(ids[i], ids[j]))
        });
        self.mrf = mrf;
        self.node_ids = ids;
        self.node_of = node_of;
        self.run_bp();
        Ok(())
    }

    /// Re-evaluate one room's evidence and propagate the change (warm start).
    fn refresh_room(&mut self, r: RoomId) -> Result<(), ConceptError> {
        let Some(&i) = self.node_of.get(&r) else {
            return self.infer();
        };
        let u = self.normalized_unary(r)?;
        self.mrf.set_unary(i, &u);
        self.run_bp();
        Ok(())
    }

    fn run_bp(&mut self) {
        let run = self.mrf.run(&self.opts);
        self.exact_fallback = None;
        if !run.converged {
            // Fallback: exact inference when the junction tree is small enough.
            let exact = self
                .factor_graph()
                .ok()
                .and_then(|(_, g)| crate::exact::exact_marginals(&g, EXACT_FALLBACK_ENTRIES).ok());
            tracing::warn!(
                iterations = run.iterations,
                max_diff = run.max_diff,
                exact_fallback = exact.is_some(),
                "conceptual map BP did not converge"
            );
            self.exact_fallback = exact;
        }
        self.stats = InferenceStats {
            iterations: run.iterations,
            updates: run.updates,
            converged: run.converged,
            max_diff: run.max_diff,
        };
    }

    /// The chain graph as a factor graph: variable i is the i-th room in id order, with its
    /// evidence factor and one φ_rc factor per door (for exact inference and checks).
    pub fn factor_graph(&self) -> Result<(Vec<RoomId>, FactorGraph), ConceptError> {
        let kc = self.model.num_categories();
        let ids: Vec<RoomId> = self.rooms.keys().copied().collect();
        let mut g = FactorGraph::new(vec![kc; ids.len()])?;
        for (i, r) in ids.iter().enumerate() {
            g.add_factor(Factor::new(vec![i], vec![kc], self.normalized_unary(*r)?)?)?;
        }
        let mut t = vec![0.0; kc * kc];
        for a in 0..kc {
            for b in 0..kc {
                // first variable fastest
                t[a + kc * b] = self.model.connectivity[a][b];
            }
        }
        for (a, b) in &self.adjacency {
            let ia = ids.iter().position(|x| x == a).expect("room exists");
            let ib = ids.iter().position(|x| x == b).expect("room exists");
            g.add_factor(Factor::new(vec![ia, ib], vec![kc, kc], t.clone())?)?;
        }
        Ok((ids, g))
    }

    // ---------------------------------------------------------------- queries

    /// P_category(room): the posterior over all categories (in knowledge order).
    pub fn category_distribution(&self, room: RoomId) -> Result<Vec<f64>, ConceptError> {
        let i = *self
            .node_of
            .get(&room)
            .ok_or(ConceptError::UnknownRoom(room.0))?;
        Ok(match &self.exact_fallback {
            Some(m) => m[i].clone(),
            None => self.mrf.belief(i),
        })
    }

    /// P(category of `room` = `category`).
    pub fn p_category(&self, room: RoomId, category: &str) -> Result<f64, ConceptError> {
        let k = self.model.category(category)?;
        Ok(self.category_distribution(room)?[k])
    }

    /// The current (thinned) rate of `class` at `location` under each category: for a room,
    /// its own rate of instances not found yet (thinned by failed searches and by the looks
    /// that counted the class, `Π (1 − s_j p_d)`: see the crate docs, *Object counts*) plus
    /// every landmark location in it (rates add, §III-A).
    pub fn rates(&self, location: Location, class: &str) -> Result<Vec<f64>, ConceptError> {
        let c = self.model.class(class)?;
        let m = &self.model;
        let kc = m.num_categories();
        let lm_rates = |l: &LandmarkId, rels: &[Relation]| -> Result<Vec<f64>, ConceptError> {
            let ls = self
                .landmarks
                .get(l)
                .ok_or(ConceptError::UnknownLandmark(l.0))?;
            let mut out = vec![0.0; kc];
            for &rel in rels {
                let t = ls.searched.get(&(rel, c)).copied().unwrap_or(1.0);
                let r = m.landmark_rate(c, rel, ls.class);
                out.iter_mut().zip(r).for_each(|(o, x)| *o += t * x);
            }
            Ok(out)
        };
        match location {
            Location::Room(r) => {
                let st = self.room(r)?;
                // Instances of a class not found yet: thinned by failed searches and by the
                // looks that counted the class (what they counted is known; what is left, each
                // of them missed).
                let unfound = |class: usize| -> f64 {
                    let looks: f64 = st
                        .places
                        .values()
                        .flat_map(|o| &o.counts)
                        .filter(|o| o.class == class)
                        .map(|o| 1.0 - o.coverage * m.count_detection)
                        .product();
                    st.searched.get(&class).copied().unwrap_or(1.0) * looks
                };
                let t = unfound(c);
                let mut out: Vec<f64> = m.room_rates[c].iter().map(|x| t * x).collect();
                for l in &st.landmarks {
                    let add = lm_rates(l, &[Relation::In, Relation::On])?;
                    out.iter_mut().zip(add).for_each(|(o, x)| *o += x);
                }
                // With `unfound_landmarks`: landmarks not found yet are subordinate locations
                // too (§III-A). Each landmark class's unfound instances (its room rate thinned
                // as above) hold the object with 1 − e^{−ν} each (compound Poisson, as in
                // `Model::unseen_room_rates`), and a failed search for the object in the room
                // thins them as it thins the room's own rate.
                if self.unfound_landmarks {
                    let searched = st.searched.get(&c).copied().unwrap_or(1.0);
                    for (lm, hold) in m.landmark_holds(c) {
                        let tl = unfound(lm) * searched;
                        for ((x, mu), h) in out.iter_mut().zip(&m.room_rates[lm]).zip(hold) {
                            *x += tl * mu * h;
                        }
                    }
                }
                Ok(out)
            }
            Location::Landmark(l, rel) => lm_rates(&l, &[rel]),
        }
    }

    /// P(ObjectAt L) = P(n_c ≥ 1 in L) = Σ_k P(k | room) (1 − exp(−λ_{L,c,k})) — eq. 1–2,
    /// mixed over the room's category posterior, with rates thinned by failed searches.
    pub fn p_object_at(&self, location: Location, class: &str) -> Result<f64, ConceptError> {
        let room = match location {
            Location::Room(r) => r,
            Location::Landmark(l, _) => {
                self.landmarks
                    .get(&l)
                    .ok_or(ConceptError::UnknownLandmark(l.0))?
                    .room
            }
        };
        let b = self.category_distribution(room)?;
        let rates = self.rates(location, class)?;
        Ok(b.iter()
            .zip(&rates)
            .map(|(p, l)| p * (1.0 - (-l).exp()))
            .sum())
    }

    /// Expected number of `class` objects at `location` (Σ_k P(k) λ_k).
    pub fn expected_count(&self, location: Location, class: &str) -> Result<f64, ConceptError> {
        let room = match location {
            Location::Room(r) => r,
            Location::Landmark(l, _) => {
                self.landmarks
                    .get(&l)
                    .ok_or(ConceptError::UnknownLandmark(l.0))?
                    .room
            }
        };
        let b = self.category_distribution(room)?;
        Ok(b.iter()
            .zip(self.rates(location, class)?)
            .map(|(p, l)| p * l)
            .sum())
    }

    /// The landmarks of a room with their class names.
    pub fn landmarks_in(&self, room: RoomId) -> Result<Vec<(LandmarkId, &str)>, ConceptError> {
        Ok(self
            .room(room)?
            .landmarks
            .iter()
            .map(|l| (*l, self.model.classes[self.landmarks[l].class].as_str()))
            .collect())
    }

    /// The six structure hypotheses of a placeholder and the categories of the rooms they
    /// would add (§III-A.1).
    pub fn placeholder_hypotheses(&self, id: PlaceholderId) -> Result<Hypotheses, ConceptError> {
        let p = self
            .placeholders
            .get(&id)
            .ok_or(ConceptError::UnknownPlaceholder(id.0))?;
        let bel = self.category_distribution(p.room)?;
        Ok(hypothesis_probabilities(&self.model, p, &bel))
    }

    /// P(the placeholder leads to a new room) = P(h3) + P(h4) + P(h5) + P(h6).
    pub fn p_new_room(&self, id: PlaceholderId) -> Result<f64, ConceptError> {
        Ok(self.placeholder_hypotheses(id)?.p_new_room())
    }

    /// P_category(placeholder): for each category, the probability that exploring the
    /// placeholder yields a new room of that category (Σ_h P(h) · P(a room of h is of it)).
    /// Not a distribution: the rest of the mass is "no new room of this category".
    pub fn p_category_placeholder(
        &self,
        id: PlaceholderId,
        category: &str,
    ) -> Result<f64, ConceptError> {
        let k = self.model.category(category)?;
        Ok(self.placeholder_hypotheses(id)?.p_category[k])
    }

    /// P(at least one `class` object in the new rooms behind the placeholder): in their open
    /// space, and with [`Self::set_unfound_landmarks`] also on and in the landmarks they are
    /// expected to hold ([`Model::unseen_room_rates`]).
    pub fn p_object_behind_placeholder(
        &self,
        id: PlaceholderId,
        class: &str,
    ) -> Result<f64, ConceptError> {
        let c = self.model.class(class)?;
        Ok(self
            .placeholder_hypotheses(id)?
            .p_object(&if self.unfound_landmarks {
                std::borrow::Cow::Owned(self.model.unseen_room_rates(c))
            } else {
                std::borrow::Cow::Borrowed(&self.model.room_rates[c][..])
            }))
    }
}
