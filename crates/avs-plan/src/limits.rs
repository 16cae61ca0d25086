//! Bounds on grounding, shared by PDDL tasks ([`crate::pddl::ground_with`]) and YAML domains
//! ([`crate::ground::ground_with`]).
//!
//! Grounding instantiates each operator with every tuple of objects its static preconditions
//! allow, so an operator's groundings multiply with every parameter no precondition
//! constrains: gripper's `move` with 8 extra unused parameters has 8⁸ ≈ 1.7·10⁷ groundings per
//! pair of rooms and ground for over 40 s past 1.8 GB before this limit. Grounding now counts
//! as it goes and stops with [`crate::PlanError::GroundingLimit`], which names the operator (or
//! state variable) that passed the limit, the resource and the limit, before the memory is
//! spent. Four resources are counted ([`GroundingResource`]):
//! * **ground operators** (default 10⁶) — distinct instantiations kept;
//! * **facts** (default 10⁶) — reached ground atoms (PDDL) or ground variables (YAML);
//! * **bytes** (default 1 GiB) — an estimate of the memory of the operators and facts kept
//!   ([`OPERATOR_BYTES`] + [`BYTES_PER_PARAMETER`] per parameter, [`FACT_BYTES`] +
//!   [`BYTES_PER_PARAMETER`] per argument), which catches operators with many parameters
//!   before their count does;
//! * **bindings tried** (default 10⁸) — partial and complete parameter tuples visited by the
//!   enumeration, over all rounds of the reachability fixpoint: the grounding's work, which
//!   can explode without keeping anything when a late precondition rejects every tuple.
//!
//! Why these defaults: measured, the largest grounding of the PDDL benchmarks in
//! `shared/data/pddl` tries 6,240 bindings and keeps an estimated 0.5 MB, and the object-search
//! domain in the `avs-eval` searches at most 15,171 bindings and 1.3 MB (a few thousand
//! operators); the defaults are more than three orders of magnitude above both. At the limits a
//! task holds about 1 GiB and grounding takes seconds (gripper's `move` with 8 unused
//! parameters now stops at 10⁶ operators after 0.1 s and 120 MB), and no search on a task of 10⁶
//! operators would finish anyway.

use crate::PlanError;

/// Estimated bytes of one ground operator apart from its parameters (schema and display text,
/// precondition and effect lists, the reachability tables' entry).
pub const OPERATOR_BYTES: usize = 256;
/// Estimated bytes of one fact apart from its arguments (name, tables' entry, variable).
pub const FACT_BYTES: usize = 128;
/// Estimated bytes per parameter of an operator or argument of a fact (index, name, display).
pub const BYTES_PER_PARAMETER: usize = 40;
/// Bytes of a binding found but not yet an operator, apart from its 8 bytes per parameter.
const FOUND_BYTES: usize = 32;

/// Limits on the size of a grounding; see the module docs for the reasons of the defaults.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GroundingLimits {
    /// Most ground operators.
    pub max_operators: usize,
    /// Most facts (PDDL ground atoms reached, YAML ground variables).
    pub max_facts: usize,
    /// Most bytes of operators and facts, estimated.
    pub max_bytes: usize,
    /// Most parameter bindings tried (partial ones included), over the whole grounding.
    pub max_bindings: usize,
}

impl Default for GroundingLimits {
    fn default() -> Self {
        Self {
            max_operators: 1_000_000,
            max_facts: 1_000_000,
            max_bytes: 1 << 30,
            max_bindings: 100_000_000,
        }
    }
}

/// What a grounding ran out of.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GroundingResource {
    /// [`GroundingLimits::max_operators`].
    Operators,
    /// [`GroundingLimits::max_facts`].
    Facts,
    /// [`GroundingLimits::max_bytes`].
    Bytes,
    /// [`GroundingLimits::max_bindings`].
    Bindings,
}

impl std::fmt::Display for GroundingResource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            GroundingResource::Operators => "ground operators",
            GroundingResource::Facts => "facts",
            GroundingResource::Bytes => "bytes (estimated)",
            GroundingResource::Bindings => "parameter bindings tried",
        })
    }
}

/// The running counts of one grounding against its limits.
pub(crate) struct Budget {
    limits: GroundingLimits,
    bindings: usize,
    bytes: usize,
}

impl Budget {
    pub(crate) fn new(limits: &GroundingLimits) -> Self {
        Self {
            limits: *limits,
            bindings: 0,
            bytes: 0,
        }
    }

    fn limit(&self, resource: GroundingResource) -> usize {
        match resource {
            GroundingResource::Operators => self.limits.max_operators,
            GroundingResource::Facts => self.limits.max_facts,
            GroundingResource::Bytes => self.limits.max_bytes,
            GroundingResource::Bindings => self.limits.max_bindings,
        }
    }

    fn exceeded(&self, what: impl Into<String>, resource: GroundingResource) -> PlanError {
        PlanError::GroundingLimit {
            what: what.into(),
            resource,
            limit: self.limit(resource) as u64,
        }
    }

    /// One more (partial) binding tried while grounding `what`.
    pub(crate) fn tried(&mut self, what: impl FnOnce() -> String) -> Result<(), PlanError> {
        self.bindings += 1;
        if self.bindings > self.limits.max_bindings {
            return Err(self.exceeded(what(), GroundingResource::Bindings));
        }
        Ok(())
    }

    /// `count` operators are kept so far, the last one from `what` with `params` parameters.
    pub(crate) fn operator(
        &mut self,
        what: impl FnOnce() -> String,
        count: usize,
        params: usize,
    ) -> Result<(), PlanError> {
        let bytes = OPERATOR_BYTES + BYTES_PER_PARAMETER * params;
        self.kept(what, GroundingResource::Operators, count, bytes)
    }

    /// `count` items of `resource` are kept so far, the last one of `bytes` added by `what`.
    fn kept(
        &mut self,
        what: impl FnOnce() -> String,
        resource: GroundingResource,
        count: usize,
        bytes: usize,
    ) -> Result<(), PlanError> {
        self.bytes += bytes;
        if count > self.limit(resource) {
            return Err(self.exceeded(what(), resource));
        }
        self.check_bytes(what)
    }

    /// Whether `count` bindings of `params` parameters found by one enumeration of `what`
    /// (held until they become operators) are already too many or too large.
    pub(crate) fn found(
        &self,
        what: impl FnOnce() -> String,
        count: usize,
        params: usize,
    ) -> Result<(), PlanError> {
        if count > self.limits.max_operators {
            return Err(self.exceeded(what(), GroundingResource::Operators));
        }
        let held = count.saturating_mul(FOUND_BYTES + 8 * params);
        if self.bytes.saturating_add(held) > self.limits.max_bytes {
            return Err(self.exceeded(what(), GroundingResource::Bytes));
        }
        Ok(())
    }

    /// `count` facts are kept so far, the last one (of `arity` arguments) added by `what`.
    pub(crate) fn fact(
        &mut self,
        what: impl FnOnce() -> String,
        count: usize,
        arity: usize,
    ) -> Result<(), PlanError> {
        let bytes = FACT_BYTES + BYTES_PER_PARAMETER * arity;
        self.kept(what, GroundingResource::Facts, count, bytes)
    }

    /// Whether `count` facts of `what` may be added (checked before they are built).
    pub(crate) fn facts_ahead(
        &self,
        what: impl FnOnce() -> String,
        count: Option<usize>,
    ) -> Result<(), PlanError> {
        if count.is_none_or(|c| c > self.limits.max_facts) {
            return Err(self.exceeded(what(), GroundingResource::Facts));
        }
        Ok(())
    }

    fn check_bytes(&self, what: impl FnOnce() -> String) -> Result<(), PlanError> {
        if self.bytes > self.limits.max_bytes {
            return Err(self.exceeded(what(), GroundingResource::Bytes));
        }
        Ok(())
    }
}
