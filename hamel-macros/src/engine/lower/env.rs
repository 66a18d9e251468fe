//! Locals and their scopes while a body is lowered.

use super::value::Value;
use crate::engine::hash::HashMap;

#[derive(Clone, Debug)]
pub struct Local {
    pub value: Value,
    pub mutable: bool,
}

/// The locals visible at a point of a body: a stack of block scopes. Each inlined call gets a
/// fresh `Env`, so a callee cannot see its caller's locals. An `if` lowers each branch in a
/// clone and merges the two afterwards.
#[derive(Clone, Debug, Default)]
pub struct Env {
    scopes: Vec<HashMap<String, Local>>,
}

impl Env {
    pub fn push(&mut self) {
        self.scopes.push(HashMap::default());
    }

    pub fn pop(&mut self) {
        self.scopes.pop();
    }

    pub fn depth(&self) -> usize {
        self.scopes.len()
    }

    pub fn bind(&mut self, name: String, value: Value, mutable: bool) {
        if self.scopes.is_empty() {
            self.push();
        }
        if let Some(scope) = self.scopes.last_mut() {
            scope.insert(name, Local { value, mutable });
        }
    }

    pub fn get(&self, name: &str) -> Option<&Local> {
        self.scopes.iter().rev().find_map(|s| s.get(name))
    }

    pub fn get_mut(&mut self, name: &str) -> Option<&mut Local> {
        self.scopes.iter_mut().rev().find_map(|s| s.get_mut(name))
    }

    /// Every binding of the outermost `depth` scopes, innermost-visible first, with the
    /// scope it lives in: what an `if` must merge after its branches ran.
    pub fn bindings(&self, depth: usize) -> Vec<(usize, String)> {
        let mut out = Vec::new();
        for (level, scope) in self.scopes.iter().enumerate().take(depth) {
            for name in scope.keys() {
                out.push((level, name.clone()));
            }
        }
        out
    }

    pub fn at(&self, level: usize, name: &str) -> Option<&Local> {
        self.scopes.get(level).and_then(|s| s.get(name))
    }

    pub fn set_at(&mut self, level: usize, name: &str, value: Value) {
        if let Some(local) = self.scopes.get_mut(level).and_then(|s| s.get_mut(name)) {
            local.value = value;
        }
    }
}
