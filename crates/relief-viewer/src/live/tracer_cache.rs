//! Tracers built when a frame first asks for them, then kept for the frames after it.

use relief_render::RenderError;
use std::collections::HashMap;
use std::hash::Hash;
use std::sync::{Arc, Mutex};

/// Tracers (of any kind `T`) by what they were built for (`K`).
pub struct TracerCache<K, T: ?Sized> {
    built: Mutex<HashMap<K, Arc<T>>>,
}

impl<K: Eq + Hash, T: ?Sized> TracerCache<K, T> {
    /// A cache holding `built`.
    pub fn new(built: HashMap<K, Arc<T>>) -> Self {
        TracerCache { built: Mutex::new(built) }
    }

    /// The tracer of `key`: the kept one, else built now by `build` and kept.
    pub fn get_or_build(
        &self,
        key: K,
        build: impl FnOnce() -> Result<Arc<T>, RenderError>,
    ) -> Result<Arc<T>, RenderError> {
        let mut built = self.built.lock().expect("no render panicked");
        if let Some(tracer) = built.get(&key) {
            return Ok(tracer.clone());
        }
        let tracer = build()?;
        built.insert(key, tracer.clone());
        Ok(tracer)
    }

    /// Forgets every tracer (their terrain changed).
    pub fn clear(&self) {
        self.built.lock().expect("no render panicked").clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tracer_is_built_once_until_cleared() {
        let cache: TracerCache<u8, str> = TracerCache::new(HashMap::new());
        let built = std::cell::Cell::new(0);
        let build = || {
            built.set(built.get() + 1);
            Ok(Arc::from("tracer"))
        };
        assert_eq!(&*cache.get_or_build(1, build).unwrap(), "tracer");
        assert_eq!(&*cache.get_or_build(1, build).unwrap(), "tracer");
        assert_eq!(built.get(), 1);
        cache.clear();
        cache.get_or_build(1, build).unwrap();
        assert_eq!(built.get(), 2);
    }
}
