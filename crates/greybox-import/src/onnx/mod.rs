//! ONNX models (`.onnx`) converted into greybox's own models — so that an ONNX model works
//! everywhere a greybox model does, the C ABI inside an FE solver included, without an ONNX
//! runtime linked into it.
//!
//! The graph must be one chain of operators on the feature tensor (as converters write
//! regression models: skl2onnx, onnxmltools for XGBoost/LightGBM, exports of small networks).
//! Supported operators:
//!
//! | operator | domain | becomes |
//! |---|---|---|
//! | `TreeEnsembleRegressor` (modes `BRANCH_LEQ`, `BRANCH_LT`, `BRANCH_GTE`, `BRANCH_GT`; aggregate `SUM`, `AVERAGE`; `post_transform` `NONE`; one target) | ai.onnx.ml | tree ensemble, splits restated exactly on the raw input |
//! | `SVMRegressor` (`LINEAR`, `POLY`, `RBF`, `SIGMOID`) | ai.onnx.ml | ε-SVR |
//! | `LinearRegressor` (one target) | ai.onnx.ml | network without hidden layer |
//! | `MatMul`, `Gemm` (constant weights), `Add`/`Sub`/`Mul`/`Div` by constants, `Relu`, `Tanh`, `Sigmoid` | ai.onnx | feed-forward network (one activation kind) |
//! | `Scaler` | ai.onnx.ml | input standardisation |
//! | `Cast`, `Identity`, `Reshape`, `Flatten`, `Squeeze`, `Unsqueeze` | ai.onnx | nothing (shape only; a float cast is kept in tree splits) |
//!
//! Anything else is refused, naming the operator. Agreement with onnxruntime: tree splits
//! exact (inputs, scalers and thresholds in float32 as the runtime evaluates them), sums to
//! float32 rounding; networks and SVMs to float32 rounding (the runtime computes in float32,
//! greybox in float64).

mod graph;
pub mod proto;
mod tree_ensemble;

use graph::{data_path, input_type, tensor_values, Attributes, Constant};
use greybox_model::family::{Family, FittedModel};
use greybox_model::matrix::{Matrix, Standardizer};
use greybox_model::mlp::{Activation, MlpModel};
use greybox_model::svr::{Kernel, SvrModel};
use prost::Message;
use proto::{data_type, NodeProto};
use std::collections::HashMap;

/// An element-wise operation by a constant (per feature, or one value for all).
#[derive(Debug, Clone)]
pub(crate) enum Elementwise {
    Add(Vec<f64>),
    Sub(Vec<f64>),
    Mul(Vec<f64>),
    Div(Vec<f64>),
    /// ai.onnx.ml Scaler: (x − offset) · scale.
    Scaler {
        offset: Vec<f64>,
        scale: Vec<f64>,
    },
    /// Round to float32 (a float tensor).
    ToF32,
}

fn at(v: &[f64], i: usize) -> f64 {
    if v.len() == 1 {
        v[0]
    } else {
        v[i]
    }
}

impl Elementwise {
    /// Its constants' lengths: each must be 1 (broadcast) or the width of the data it meets.
    fn lengths(&self) -> Vec<usize> {
        match self {
            Elementwise::Add(v)
            | Elementwise::Sub(v)
            | Elementwise::Mul(v)
            | Elementwise::Div(v) => vec![v.len()],
            Elementwise::Scaler { offset, scale } => vec![offset.len(), scale.len()],
            Elementwise::ToF32 => Vec::new(),
        }
    }

    /// Refuses constants that neither broadcast nor match the `width` features they act on.
    pub(crate) fn check_width(ops: &[Elementwise], width: usize) -> Result<(), String> {
        Self::check_lengths(ops, width, |len| len == width)
    }

    /// Refuses constants that neither broadcast nor cover the first `width` features (a tree
    /// ensemble reads only the features it splits on, which may be fewer than its inputs).
    pub(crate) fn check_covers(ops: &[Elementwise], width: usize) -> Result<(), String> {
        Self::check_lengths(ops, width, |len| len >= width)
    }

    fn check_lengths(
        ops: &[Elementwise],
        width: usize,
        fits: impl Fn(usize) -> bool,
    ) -> Result<(), String> {
        match ops
            .iter()
            .flat_map(Elementwise::lengths)
            .find(|&len| len != 1 && !fits(len))
        {
            Some(len) => Err(format!(
                "an element-wise constant of {len} values meets data of {width} columns (expected 1 or {width})"
            )),
            None => Ok(()),
        }
    }

    /// Element `i`, in float32 arithmetic when `f32` (a float tensor), as the runtime does.
    pub(crate) fn apply(&self, i: usize, x: f64, f32: bool) -> f64 {
        let r = |v: f64| if f32 { v as f32 as f64 } else { v };
        let c = |v: &[f64]| r(at(v, i));
        match self {
            Elementwise::Add(v) => r(x + c(v)),
            Elementwise::Sub(v) => r(x - c(v)),
            Elementwise::Mul(v) => r(x * c(v)),
            Elementwise::Div(v) => r(x / c(v)),
            Elementwise::Scaler { offset, scale } => r(r(x - c(offset)) * c(scale)),
            Elementwise::ToF32 => x as f32 as f64,
        }
    }
    /// The map as z = a·x + b for element `i`.
    fn affine(&self, i: usize) -> (f64, f64) {
        match self {
            Elementwise::Add(v) => (1.0, at(v, i)),
            Elementwise::Sub(v) => (1.0, -at(v, i)),
            Elementwise::Mul(v) => (at(v, i), 0.0),
            Elementwise::Div(v) => (1.0 / at(v, i), 0.0),
            Elementwise::Scaler { offset, scale } => (at(scale, i), -at(offset, i) * at(scale, i)),
            Elementwise::ToF32 => (1.0, 0.0),
        }
    }
}

/// One stage of the chain.
enum Stage<'a> {
    Elementwise(Elementwise),
    /// y = x·W + bias; `w` is n_in × n_out, row-major.
    Dense {
        w: Vec<f64>,
        n_in: usize,
        n_out: usize,
        bias: Vec<f64>,
    },
    Activation(Activation),
    /// A terminal ai.onnx.ml operator.
    Terminal(&'a NodeProto),
}

/// The converted model.
pub struct OnnxModel {
    pub model: FittedModel,
    pub family: Family,
    pub n_features: usize,
    /// The producer, e.g. "skl2onnx 1.20.0".
    pub producer: String,
    /// The operators, e.g. "Scaler → SVMRegressor".
    pub operators: String,
}

/// A tree ensemble whose graph is named after a forest (skl2onnx names the graph
/// `ONNX(RandomForestRegressor)` and writes the forest as a sum of trees with its weights
/// divided by their number, so the sum alone cannot tell it from boosting): a random forest.
/// An `AVERAGE` ensemble is one already ([`tree_ensemble::convert`]).
fn forest_by_name(family: Family, graph: Option<&str>) -> Family {
    let named_forest = graph.is_some_and(|n| {
        let n = n.to_ascii_lowercase();
        n.contains("randomforest") || n.contains("extratrees") || n.contains("random_forest")
    });
    match family {
        Family::GradientBoosting if named_forest => Family::RandomForest,
        f => f,
    }
}

/// Convert an ONNX model's bytes.
pub fn convert(bytes: &[u8]) -> Result<OnnxModel, String> {
    let m = proto::ModelProto::decode(bytes).map_err(|e| format!("not an ONNX model: {e}"))?;
    let g = m.graph.as_ref().ok_or("the ONNX model has no graph")?;
    let mut constants: HashMap<String, Constant> = HashMap::new();
    for t in &g.initializer {
        constants.insert(t.name.clone().unwrap_or_default(), tensor_values(t)?);
    }
    for n in &g.node {
        if n.op_type.as_deref() == Some("Constant") {
            let a = n
                .attribute
                .iter()
                .find_map(|a| a.t.as_ref())
                .ok_or("a Constant node without a tensor")?;
            constants.insert(
                n.output.first().cloned().unwrap_or_default(),
                tensor_values(a)?,
            );
        }
    }
    let path = data_path(g, &constants, &|n| {
        let op = n.op_type.as_deref().unwrap_or("");
        if SUPPORTED.contains(&op) {
            Ok(())
        } else {
            Err(unsupported(n))
        }
    })?;
    let mut f32 = input_type(g) == Some(data_type::FLOAT);
    let mut stages = Vec::new();
    if f32 {
        stages.push(Stage::Elementwise(Elementwise::ToF32));
    }
    for node in &path {
        stage(node, &constants, &mut stages, &mut f32)?;
    }
    let operators = path
        .iter()
        .filter_map(|n| n.op_type.clone())
        .collect::<Vec<_>>()
        .join(" → ");
    let producer = format!(
        "{} {}",
        m.producer_name
            .clone()
            .unwrap_or_else(|| "unknown producer".into()),
        m.producer_version.clone().unwrap_or_default()
    )
    .trim()
    .to_string();
    let (model, family, n_features) = assemble(stages)?;
    let family = forest_by_name(family, g.name.as_deref());
    Ok(OnnxModel {
        model,
        family,
        n_features,
        producer,
        operators,
    })
}

fn constant<'a>(
    c: &'a HashMap<String, Constant>,
    node: &NodeProto,
    k: usize,
) -> Result<&'a Constant, String> {
    node.input.get(k).and_then(|n| c.get(n)).ok_or_else(|| {
        format!(
            "{} node '{}': input {k} must be a constant",
            node.op_type.as_deref().unwrap_or("?"),
            node.name.as_deref().unwrap_or("")
        )
    })
}

/// The constant operand of a binary element-wise node (whichever input is constant).
fn operand(c: &HashMap<String, Constant>, node: &NodeProto) -> Result<(Vec<f64>, bool), String> {
    for (k, name) in node.input.iter().enumerate() {
        if let Some(v) = c.get(name) {
            return Ok((v.values.clone(), k == 0));
        }
    }
    Err(format!(
        "{} node '{}' has no constant operand",
        node.op_type.as_deref().unwrap_or("?"),
        node.name.as_deref().unwrap_or("")
    ))
}

fn stage<'a>(
    node: &'a NodeProto,
    c: &HashMap<String, Constant>,
    out: &mut Vec<Stage<'a>>,
    f32: &mut bool,
) -> Result<(), String> {
    let op = node.op_type.as_deref().unwrap_or("");
    let a = Attributes::of(node);
    match op {
        "Identity" | "Reshape" | "Flatten" | "Squeeze" | "Unsqueeze" => {}
        "Cast" => {
            *f32 = a.int("to", 0) == data_type::FLOAT as i64;
            if *f32 {
                out.push(Stage::Elementwise(Elementwise::ToF32));
            }
        }
        "Scaler" => out.push(Stage::Elementwise(Elementwise::Scaler {
            offset: a.floats("offset")?,
            scale: a.floats("scale")?,
        })),
        "Add" | "Sub" | "Mul" | "Div" => {
            let (v, constant_first) = operand(c, node)?;
            let e = match (op, constant_first) {
                ("Add", _) => Elementwise::Add(v),
                ("Mul", _) => Elementwise::Mul(v),
                ("Sub", false) => Elementwise::Sub(v),
                ("Div", false) => Elementwise::Div(v),
                _ => {
                    return Err(format!(
                        "{op} node '{}' with the constant first is not supported",
                        node.name.as_deref().unwrap_or("")
                    ))
                }
            };
            out.push(Stage::Elementwise(e));
        }
        "MatMul" => {
            let w = constant(c, node, 1)?;
            let [n_in, n_out] = w.dims[..] else {
                return Err(format!("MatMul weights of shape {:?}", w.dims));
            };
            out.push(Stage::Dense {
                w: w.values.clone(),
                n_in,
                n_out,
                bias: vec![0.0; n_out],
            });
        }
        "Gemm" => out.push(gemm(node, c, &a)?),
        "Relu" => out.push(Stage::Activation(Activation::Relu)),
        "Tanh" => out.push(Stage::Activation(Activation::Tanh)),
        "Sigmoid" => out.push(Stage::Activation(Activation::Logistic)),
        "LinearRegressor" => {
            if a.int("targets", 1) != 1 || a.string("post_transform", "NONE") != "NONE" {
                return Err(
                    "LinearRegressor: only one target without post_transform is supported".into(),
                );
            }
            let w = a.require_floats("coefficients")?;
            let b = a.floats("intercepts")?;
            out.push(Stage::Dense {
                n_in: w.len(),
                n_out: 1,
                w,
                bias: vec![b.first().copied().unwrap_or(0.0)],
            });
        }
        "TreeEnsembleRegressor" | "SVMRegressor" => out.push(Stage::Terminal(node)),
        _ => return Err(unsupported(node)),
    }
    Ok(())
}

/// The operators [`convert`] reads.
const SUPPORTED: [&str; 20] = [
    "Identity",
    "Reshape",
    "Flatten",
    "Squeeze",
    "Unsqueeze",
    "Cast",
    "Scaler",
    "Add",
    "Sub",
    "Mul",
    "Div",
    "MatMul",
    "Gemm",
    "Relu",
    "Tanh",
    "Sigmoid",
    "LinearRegressor",
    "TreeEnsembleRegressor",
    "SVMRegressor",
    "Constant",
];

fn unsupported(node: &NodeProto) -> String {
    format!(
        "operator {} ({}) is not supported; supported: {}",
        node.op_type.as_deref().unwrap_or("?"),
        node.domain
            .as_deref()
            .filter(|d| !d.is_empty())
            .unwrap_or("ai.onnx"),
        SUPPORTED.join(", ")
    )
}

/// Gemm: Y = alpha · A·B' + beta · C with B' = Bᵀ when transB (A is the data, transA = 0).
fn gemm(
    node: &NodeProto,
    c: &HashMap<String, Constant>,
    a: &Attributes,
) -> Result<Stage<'static>, String> {
    if a.int("transA", 0) != 0 {
        return Err("Gemm with transA = 1 is not supported".into());
    }
    let b = constant(c, node, 1)?;
    let [r, k] = b.dims[..] else {
        return Err(format!("Gemm weights of shape {:?}", b.dims));
    };
    let (alpha, beta) = (a.float("alpha", 1.0), a.float("beta", 1.0));
    let trans = a.int("transB", 0) != 0;
    let (n_in, n_out) = if trans { (k, r) } else { (r, k) };
    let mut w = vec![0.0; n_in * n_out];
    for i in 0..n_in {
        for o in 0..n_out {
            w[i * n_out + o] = alpha
                * if trans {
                    b.values[o * k + i]
                } else {
                    b.values[i * k + o]
                };
        }
    }
    let bias = match node.input.get(2).filter(|n| !n.is_empty()) {
        Some(_) => {
            let cv = constant(c, node, 2)?;
            (0..n_out).map(|o| beta * at(&cv.values, o)).collect()
        }
        None => vec![0.0; n_out],
    };
    Ok(Stage::Dense {
        w,
        n_in,
        n_out,
        bias,
    })
}

/// The greybox model of a chain of stages.
fn assemble(stages: Vec<Stage>) -> Result<(FittedModel, Family, usize), String> {
    let terminal = stages.iter().position(|s| matches!(s, Stage::Terminal(_)));
    if let Some(t) = terminal {
        if t + 1 != stages.len()
            && stages[t + 1..]
                .iter()
                .any(|s| !matches!(s, Stage::Elementwise(Elementwise::ToF32)))
        {
            return Err(
                "operators after a TreeEnsembleRegressor/SVMRegressor are not supported".into(),
            );
        }
        let pre: Vec<Elementwise> = stages[..t]
            .iter()
            .map(|s| match s {
                Stage::Elementwise(e) => Ok(e.clone()),
                _ => {
                    Err("only scalers may precede a TreeEnsembleRegressor/SVMRegressor".to_string())
                }
            })
            .collect::<Result<_, _>>()?;
        let Stage::Terminal(node) = &stages[t] else {
            unreachable!()
        };
        return match node.op_type.as_deref() {
            Some("TreeEnsembleRegressor") => tree_ensemble::convert(node, &pre),
            _ => svm(node, &pre),
        };
    }
    network(stages)
}

/// Per feature, the pre-processing chain as one standardiser (affine maps composed).
fn standardizer(pre: &[Elementwise], n: usize) -> Standardizer {
    crate::scaler::compose_affine(n, |i| Some(pre.iter().map(|e| e.affine(i)).collect()))
        .expect("element-wise maps are all affine")
}

fn svm(node: &NodeProto, pre: &[Elementwise]) -> Result<(FittedModel, Family, usize), String> {
    let a = Attributes::of(node);
    if a.int("one_class", 0) != 0 || a.string("post_transform", "NONE") != "NONE" {
        return Err("SVMRegressor: one-class models and post transforms are not supported".into());
    }
    let kernel = match a.string("kernel_type", "LINEAR").as_str() {
        "LINEAR" => Kernel::Linear,
        "POLY" => Kernel::Poly,
        "RBF" => Kernel::Rbf,
        "SIGMOID" => Kernel::Sigmoid,
        k => return Err(format!("SVMRegressor kernel {k} is not supported")),
    };
    let params = a.floats("kernel_params")?;
    let coef = a.require_floats("coefficients")?;
    let sv = a.require_floats("support_vectors")?;
    let n_sv = a.int("n_supports", coef.len() as i64) as usize;
    if n_sv == 0 || coef.len() != n_sv || sv.len() % n_sv != 0 {
        return Err(format!(
            "SVMRegressor: {} coefficients, {} support-vector values for {n_sv} supports",
            coef.len(),
            sv.len()
        ));
    }
    let n = sv.len() / n_sv;
    Elementwise::check_width(pre, n)?;
    let rho = a.floats("rho")?.first().copied().unwrap_or(0.0);
    Ok((
        FittedModel::Svr(SvrModel {
            scaler: standardizer(pre, n),
            kernel,
            gamma: params.first().copied().unwrap_or(0.0),
            coef0: params.get(1).copied().unwrap_or(0.0),
            degree: params.get(2).copied().unwrap_or(3.0) as u32,
            support: Matrix {
                n_rows: n_sv,
                n_cols: n,
                data: sv,
            },
            coef,
            // ONNX: Σ cᵢ K + rho; greybox: Σ cᵢ K − ρ
            rho: -rho,
            iterations: 0,
        }),
        Family::Svr,
        n,
    ))
}

/// Dense layers separated by one kind of activation, scalers in front: an MLP.
fn network(stages: Vec<Stage>) -> Result<(FittedModel, Family, usize), String> {
    let mut pre = Vec::new();
    let mut layers: Vec<(Vec<f64>, usize, usize, Vec<f64>)> = Vec::new();
    let mut activation: Option<Activation> = None;
    let mut after_activation = true;
    for s in stages {
        match s {
            Stage::Elementwise(Elementwise::ToF32) => {}
            Stage::Elementwise(e) if layers.is_empty() => pre.push(e),
            Stage::Elementwise(e) => {
                if after_activation {
                    return Err(
                        "an element-wise operation after an activation is not supported".into(),
                    );
                }
                let (w, n_in, n_out, bias) = layers.last_mut().expect("a layer");
                Elementwise::check_width(std::slice::from_ref(&e), *n_out)?;
                for o in 0..*n_out {
                    let (ea, eb) = e.affine(o);
                    for i in 0..*n_in {
                        w[i * *n_out + o] *= ea;
                    }
                    bias[o] = ea * bias[o] + eb;
                }
            }
            Stage::Dense {
                w,
                n_in,
                n_out,
                bias,
            } => {
                if !after_activation {
                    return Err(
                        "two linear layers without an activation between them are not supported"
                            .into(),
                    );
                }
                if layers.is_empty() {
                    Elementwise::check_width(&pre, n_in)?;
                }
                if let Some(prev) = layers.last() {
                    if prev.2 != n_in {
                        return Err(format!(
                            "a layer of {n_in} inputs follows one of {} outputs",
                            prev.2
                        ));
                    }
                }
                layers.push((w, n_in, n_out, bias));
                after_activation = false;
            }
            Stage::Activation(act) => {
                if layers.is_empty() || after_activation {
                    return Err("an activation must follow a linear layer".into());
                }
                if activation.is_some_and(|a| a != act) {
                    return Err("hidden layers with different activations are not supported".into());
                }
                activation = Some(act);
                after_activation = true;
            }
            Stage::Terminal(_) => unreachable!("handled by assemble"),
        }
    }
    if layers.is_empty() || after_activation {
        return Err(
            "the chain must end in a linear layer (an output activation is not supported)".into(),
        );
    }
    let n = layers[0].1;
    if layers.last().is_some_and(|l| l.2 != 1) {
        return Err("the network must have one output".into());
    }
    let mut sizes = vec![n];
    sizes.extend(layers.iter().map(|l| l.2));
    Ok((
        FittedModel::Mlp(MlpModel {
            scaler: standardizer(&pre, n),
            y_mean: 0.0,
            y_scale: 1.0,
            activation: activation.unwrap_or(Activation::Identity),
            sizes,
            weights: layers.iter().map(|l| l.0.clone()).collect(),
            biases: layers.iter().map(|l| l.3.clone()).collect(),
            epochs: 0,
            best_epoch: 0,
        }),
        Family::Mlp,
        n,
    ))
}
