//! Sampler objects (GL ES 3.0 §3.8.2): a sampler bound to a texture unit replaces the
//! sampling parameters of whatever texture the unit holds. The translation keeps the
//! objects; the context keeps, per unit, the state of the sampler bound there.

use super::{Context, Fallible, MAX_TEXTURE_UNITS, TextureObject};
use crate::program::SamplerState;

impl Context {
    /// `bind_sampler` (`Some`) and `unbind_sampler` (`None`).
    pub(super) fn bind_sampler(&mut self, unit: u32, sampler: Option<SamplerState>) -> Fallible {
        if unit >= MAX_TEXTURE_UNITS {
            return Err(format!("texture unit {unit} is out of range (0 to {})", MAX_TEXTURE_UNITS - 1));
        }
        self.state.unit_samplers[unit as usize] = sampler;
        Ok(())
    }

    /// How unit `unit` samples texture `t`: with the unit's sampler object, else with the
    /// texture's parameters.
    pub(super) fn unit_sampler(&self, unit: u32, t: &TextureObject) -> SamplerState {
        self.state.unit_samplers.get(unit as usize).copied().flatten().unwrap_or(t.sampler)
    }
}
