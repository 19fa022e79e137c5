//! Feed-forward networks for inference: the activation, the training hyperparameters (plain
//! data, stored in model files) and the fitted network, which predicts one point without
//! allocating. Training is `greybox-learn`'s `mlp` module.

use crate::matrix::Standardizer;
use crate::predictor::Predictor;
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Activation {
    Relu,
    Tanh,
    /// 1 / (1 + e^(−v)) (scikit-learn's `logistic`).
    Logistic,
    /// v (scikit-learn's `identity`).
    Identity,
}

impl Activation {
    /// The activation's name (its [`Choice`](greybox_core::choice::Choice) name).
    pub fn name(self) -> &'static str {
        greybox_core::choice::Choice::name(self)
    }
    /// The activation of a pre-activation value.
    #[inline]
    pub fn apply(self, v: f64) -> f64 {
        match self {
            Activation::Relu => v.max(0.0),
            Activation::Tanh => v.tanh(),
            Activation::Logistic => 1.0 / (1.0 + (-v).exp()),
            Activation::Identity => v,
        }
    }
}

greybox_core::choice!(
    Activation,
    "mlp.activation",
    [Relu => "relu", Tanh => "tanh", Logistic => "logistic", Identity => "identity"],
    text
);

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MlpParams {
    pub hidden_layers: Vec<usize>,
    pub activation: Activation,
    /// Adam step size.
    pub learning_rate: f64,
    /// L2 penalty α.
    pub alpha: f64,
    /// Mini-batch size (`None`: min(200, n)).
    pub batch_size: Option<usize>,
    /// Epoch limit.
    pub max_epochs: usize,
    /// Hold out this fraction for early stopping (0: no early stopping, train all epochs).
    pub validation_fraction: f64,
    pub n_iter_no_change: usize,
    pub tol: f64,
}

impl MlpParams {
    /// The grid-relevant values, e.g. `hidden=(64,32), activation=relu, learning_rate=0.01`.
    pub fn label(&self) -> String {
        format!(
            "hidden=({}), activation={}, learning_rate={}",
            self.hidden_layers
                .iter()
                .map(|h| h.to_string())
                .collect::<Vec<_>>()
                .join(","),
            self.activation.name(),
            self.learning_rate
        )
    }
}

impl Default for MlpParams {
    fn default() -> Self {
        MlpParams {
            hidden_layers: vec![32, 16],
            activation: Activation::Relu,
            learning_rate: 0.001,
            alpha: 1e-4,
            batch_size: None,
            max_epochs: 200,
            validation_fraction: 0.1,
            n_iter_no_change: 10,
            tol: 1e-4,
        }
    }
}

/// Widest layer a single-point prediction handles without allocating.
pub const MAX_WIDTH: usize = 256;

/// Width of one hidden layer.
pub type LayerWidth = greybox_core::count::Count<1, { MAX_WIDTH as u64 }>;
/// Most hidden layers of a network.
pub const MAX_LAYERS: usize = 16;
/// Epoch limit of training: each is a pass over the rows.
pub type Epochs = greybox_core::count::Count<1, 1_000_000>;

/// A fitted network. Layer k maps `sizes[k]` → `sizes[k+1]`; `weights[k]` is row-major
/// (`sizes[k]` × `sizes[k+1]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MlpModel {
    pub scaler: Standardizer,
    pub y_mean: f64,
    pub y_scale: f64,
    pub activation: Activation,
    pub sizes: Vec<usize>,
    pub weights: Vec<Vec<f64>>,
    pub biases: Vec<Vec<f64>>,
    /// Epochs trained and the epoch whose weights were kept.
    pub epochs: usize,
    pub best_epoch: usize,
}

impl Predictor for MlpModel {
    #[inline]
    fn predict_one(&self, x: &[f64]) -> f64 {
        let mut a = [0.0; MAX_WIDTH];
        let mut b = [0.0; MAX_WIDTH];
        let p = self.sizes[0];
        a[..p].copy_from_slice(&x[..p]);
        self.scaler.transform_in_place(&mut a[..p]);
        let last = self.sizes.len() - 1;
        for k in 0..last {
            let (fi, fo) = (self.sizes[k], self.sizes[k + 1]);
            b[..fo].copy_from_slice(&self.biases[k]);
            let w = &self.weights[k];
            for i in 0..fi {
                let v = a[i];
                for (o, wv) in b[..fo].iter_mut().zip(&w[i * fo..(i + 1) * fo]) {
                    *o += v * wv;
                }
            }
            if k + 1 < last {
                for o in b[..fo].iter_mut() {
                    *o = self.activation.apply(*o);
                }
            }
            std::mem::swap(&mut a, &mut b);
        }
        a[0] * self.y_scale + self.y_mean
    }
}
