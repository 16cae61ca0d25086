//! The last answer of a pure function, kept with the input it was computed from.
//!
//! Most map updates see the known grid of the one before (a look, a turn, the sync after a
//! short move), and what is derived from it — door hypotheses, placeholders, unvisited areas —
//! is a pure function of the grid and a few other inputs. A [`Memo`] keeps the last input and
//! answer and computes again only when the input differs (compared whole, so it can never
//! hand back a stale answer).
//!
//! ```
//! use avs_map::memo::Memo;
//! let mut memo = Memo::default();
//! let mut calls = 0;
//! let mut square = |x: i32, memo: &mut Memo<i32, i32>| {
//!     memo.get_or_insert_with(x, || {
//!         calls += 1;
//!         x * x
//!     })
//! };
//! assert_eq!(square(3, &mut memo), 9);
//! assert_eq!(square(3, &mut memo), 9);
//! assert_eq!(square(4, &mut memo), 16);
//! drop(square);
//! assert_eq!(calls, 2);
//! ```

/// The last (input, answer) pair of a pure function.
#[derive(Debug, Clone)]
pub struct Memo<K, V> {
    last: Option<(K, V)>,
}

impl<K, V> Default for Memo<K, V> {
    fn default() -> Self {
        Self { last: None }
    }
}

impl<K: PartialEq, V: Clone> Memo<K, V> {
    /// The answer for `key`: the kept one when `key` equals the last input, else `compute()`'s,
    /// which is kept for next time.
    pub fn get_or_insert_with(&mut self, key: K, compute: impl FnOnce() -> V) -> V {
        let value = match self.last.take() {
            Some((k, v)) if k == key => v,
            _ => compute(),
        };
        self.last = Some((key, value.clone()));
        value
    }

    /// As [`Self::get_or_insert_with`] for a computation that may fail; a failure keeps
    /// nothing.
    pub fn try_get_or_insert_with<E>(
        &mut self,
        key: K,
        compute: impl FnOnce() -> Result<V, E>,
    ) -> Result<V, E> {
        let value = match self.last.take() {
            Some((k, v)) if k == key => v,
            _ => compute()?,
        };
        self.last = Some((key, value.clone()));
        Ok(value)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_new_input_is_computed_and_a_repeated_one_is_not() {
        let mut memo: Memo<Vec<u8>, usize> = Memo::default();
        let mut calls = 0;
        for (input, want) in [
            (vec![1, 2], 2),
            (vec![1, 2], 2),
            (vec![1], 1),
            (vec![1, 2], 2),
        ] {
            let got = memo.get_or_insert_with(input.clone(), || {
                calls += 1;
                input.len()
            });
            assert_eq!(got, want);
        }
        // Only the last input is kept: [1, 2] is computed again after [1].
        assert_eq!(calls, 3);
    }

    #[test]
    fn a_failed_computation_keeps_nothing() {
        let mut memo: Memo<u8, u8> = Memo::default();
        assert_eq!(
            memo.try_get_or_insert_with(1, || Err::<u8, ()>(())),
            Err(())
        );
        let mut calls = 0;
        let mut ok = |memo: &mut Memo<u8, u8>| {
            memo.try_get_or_insert_with(1, || {
                calls += 1;
                Ok::<u8, ()>(7)
            })
        };
        assert_eq!(ok(&mut memo), Ok(7));
        assert_eq!(ok(&mut memo), Ok(7));
        assert_eq!(calls, 1);
    }
}
