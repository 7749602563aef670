//! One piece of GPU state specialised by a hashable key, as bevy specialises its pipelines
//! by a key: built on the first use of a key, kept while the key stays, and rebuilt when
//! it changes. A failed build keeps the state that was there.

/// State `V` built for the key `K` (see the module docs).
pub(crate) struct Specialized<K, V> {
    slot: Option<(K, V)>,
}

impl<K, V> Default for Specialized<K, V> {
    fn default() -> Self {
        Self { slot: None }
    }
}

impl<K: Clone + Eq + std::hash::Hash, V> Specialized<K, V> {
    /// The state for `key`: the kept one when it was built for `key`, else `build(key)`,
    /// which replaces it only when it succeeds.
    ///
    /// # Errors
    /// What `build` returns; the kept state stays then.
    pub(crate) fn get_or_build<E>(
        &mut self,
        key: &K,
        build: impl FnOnce(&K) -> Result<V, E>,
    ) -> Result<&mut V, E> {
        let slot = match self.slot.take() {
            Some((k, v)) if k == *key => self.slot.insert((k, v)),
            old => match build(key) {
                Ok(v) => self.slot.insert((key.clone(), v)),
                Err(e) => {
                    self.slot = old;
                    return Err(e);
                }
            },
        };
        Ok(&mut slot.1)
    }

    /// The state built last, whatever its key.
    pub(crate) fn get(&self) -> Option<&V> {
        self.slot.as_ref().map(|(_, v)| v)
    }

    /// The state built last, mutably.
    pub(crate) fn get_mut(&mut self) -> Option<&mut V> {
        self.slot.as_mut().map(|(_, v)| v)
    }

    /// Drops the state (a new model: every piece of it refers to the old one).
    pub(crate) fn clear(&mut self) {
        self.slot = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kept_while_the_key_stays_rebuilt_when_it_changes_kept_when_a_build_fails() {
        let mut builds = 0;
        let mut s: Specialized<u32, String> = Specialized::default();
        let mut build = |k: &u32| -> Result<String, ()> {
            builds += 1;
            Ok(format!("built for {k}"))
        };
        assert_eq!(
            s.get_or_build(&1, &mut build).cloned(),
            Ok("built for 1".into())
        );
        assert_eq!(
            s.get_or_build(&1, &mut build).cloned(),
            Ok("built for 1".into())
        );
        assert_eq!(
            s.get_or_build(&2, &mut build).cloned(),
            Ok("built for 2".into())
        );
        assert_eq!(builds, 2);
        assert_eq!(s.get_or_build(&3, |_| Err("bad")).cloned(), Err("bad"));
        assert_eq!(s.get().cloned(), Some("built for 2".into()));
        s.clear();
        assert!(s.get().is_none());
    }
}
