//! Reading an ONNX graph: initializers as f64 arrays, node attributes by name, and the single
//! data path from the graph's input to its output.

use super::proto::{data_type, AttributeProto, GraphProto, NodeProto, TensorProto};
use std::collections::HashMap;

/// A constant tensor: shape and values (f64, exact for float and double data).
#[derive(Debug, Clone)]
pub struct Constant {
    pub dims: Vec<usize>,
    pub values: Vec<f64>,
}

/// The most values a constant tensor of an imported model may hold (2²⁴: an MLP of a few
/// thousand weights or a scaler holds far fewer; a shape beyond this is a damaged file, refused
/// before its values are allocated).
pub const MAX_TENSOR_VALUES: usize = 1 << 24;

/// A tensor's dimensions: each at least 0 (a negative one is a damaged file, never read as 0).
fn tensor_dims(name: &str, dims: &[i64]) -> Result<Vec<usize>, String> {
    dims.iter()
        .map(|d| {
            usize::try_from(*d)
                .map_err(|_| format!("tensor '{name}' has a negative dimension {d} in {dims:?}"))
        })
        .collect()
}

/// The values of a tensor as f64 (float, double, int32, int64; inline or raw little-endian).
pub fn tensor_values(t: &TensorProto) -> Result<Constant, String> {
    let name = t.name.clone().unwrap_or_default();
    if t.data_location == Some(1) {
        return Err(format!(
            "tensor '{name}' is stored in an external file (not supported)"
        ));
    }
    let dims = tensor_dims(&name, &t.dims)?;
    let n = dims
        .iter()
        .try_fold(1usize, |a, d| a.checked_mul(*d))
        .filter(|n| *n <= MAX_TENSOR_VALUES)
        .ok_or_else(|| {
            format!(
                "tensor '{name}' has shape {dims:?}: more than {MAX_TENSOR_VALUES} values, beyond any friction model (a damaged or foreign file)"
            )
        })?;
    let raw = t.raw_data.as_deref().unwrap_or(&[]);
    // the stated shape against the bytes held, before anything is allocated
    let width = match t.data_type.unwrap_or(0) {
        data_type::FLOAT | data_type::INT32 => 4,
        _ => 8,
    };
    if !raw.is_empty() && raw.len() != n * width {
        return Err(format!(
            "tensor '{name}': {} bytes of raw data for shape {dims:?} ({} values of {width} bytes)",
            raw.len(),
            n
        ));
    }
    let values: Vec<f64> = match t.data_type.unwrap_or(0) {
        data_type::FLOAT if !raw.is_empty() => raw
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64)
            .collect(),
        data_type::FLOAT => t.float_data.iter().map(|v| *v as f64).collect(),
        data_type::DOUBLE if !raw.is_empty() => raw
            .chunks_exact(8)
            .map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes")))
            .collect(),
        data_type::DOUBLE => t.double_data.clone(),
        data_type::INT64 if !raw.is_empty() => raw
            .chunks_exact(8)
            .map(|b| i64::from_le_bytes(b.try_into().expect("8 bytes")) as f64)
            .collect(),
        data_type::INT64 => t.int64_data.iter().map(|v| *v as f64).collect(),
        data_type::INT32 => t.int32_data.iter().map(|v| *v as f64).collect(),
        other => {
            return Err(format!(
                "tensor '{name}' has data type {other} (supported: float, double, int32, int64)"
            ))
        }
    };
    if values.len() != n {
        return Err(format!(
            "tensor '{name}': {} values for shape {dims:?}",
            values.len()
        ));
    }
    Ok(Constant { dims, values })
}

/// A node's attributes by name.
pub struct Attributes<'a> {
    node: &'a NodeProto,
    by_name: HashMap<&'a str, &'a AttributeProto>,
}

impl<'a> Attributes<'a> {
    pub fn of(node: &'a NodeProto) -> Self {
        let by_name = node
            .attribute
            .iter()
            .filter_map(|a| a.name.as_deref().map(|n| (n, a)))
            .collect();
        Attributes { node, by_name }
    }
    fn what(&self, name: &str) -> String {
        format!(
            "{} node '{}', attribute '{name}'",
            self.node.op_type.as_deref().unwrap_or("?"),
            self.node.name.as_deref().unwrap_or("")
        )
    }
    pub fn int(&self, name: &str, default: i64) -> i64 {
        self.by_name.get(name).and_then(|a| a.i).unwrap_or(default)
    }
    pub fn float(&self, name: &str, default: f64) -> f64 {
        self.by_name
            .get(name)
            .and_then(|a| a.f)
            .map_or(default, |f| f as f64)
    }
    pub fn string(&self, name: &str, default: &str) -> String {
        self.by_name
            .get(name)
            .and_then(|a| a.s.as_deref())
            .map_or(default.to_string(), |s| {
                String::from_utf8_lossy(s).into_owned()
            })
    }
    pub fn ints(&self, name: &str) -> Vec<i64> {
        self.by_name
            .get(name)
            .map(|a| a.ints.clone())
            .unwrap_or_default()
    }
    pub fn strings(&self, name: &str) -> Vec<String> {
        self.by_name
            .get(name)
            .map(|a| {
                a.strings
                    .iter()
                    .map(|s| String::from_utf8_lossy(s).into_owned())
                    .collect()
            })
            .unwrap_or_default()
    }
    /// Floats from `name`, or from the double tensor `name_as_tensor` (ONNX-ML opset ≥ 3).
    pub fn floats(&self, name: &str) -> Result<Vec<f64>, String> {
        if let Some(t) = self
            .by_name
            .get(format!("{name}_as_tensor").as_str())
            .and_then(|a| a.t.as_ref())
        {
            return tensor_values(t)
                .map(|c| c.values)
                .map_err(|e| format!("{}: {e}", self.what(name)));
        }
        Ok(self
            .by_name
            .get(name)
            .map(|a| a.floats.iter().map(|v| *v as f64).collect())
            .unwrap_or_default())
    }
    pub fn require_floats(&self, name: &str) -> Result<Vec<f64>, String> {
        let v = self.floats(name)?;
        if v.is_empty() {
            return Err(format!("{}: missing", self.what(name)));
        }
        Ok(v)
    }
}

/// The nodes on the path from the graph's one input to its first output, in order, each
/// with its one data input's position; every other input of a node must be a constant.
pub fn data_path<'a>(
    g: &'a GraphProto,
    constants: &HashMap<String, Constant>,
    supported: &dyn Fn(&NodeProto) -> Result<(), String>,
) -> Result<Vec<&'a NodeProto>, String> {
    let input = match g
        .input
        .iter()
        .filter(|i| !constants.contains_key(i.name.as_deref().unwrap_or("")))
        .collect::<Vec<_>>()[..]
    {
        [one] => one.name.clone().unwrap_or_default(),
        ref more => {
            return Err(format!(
                "the graph has {} inputs; one feature tensor is supported",
                more.len()
            ))
        }
    };
    let output = g
        .output
        .first()
        .and_then(|o| o.name.clone())
        .ok_or("the graph has no output")?;
    let mut current = input;
    let mut path = Vec::new();
    let mut used = vec![false; g.node.len()];
    while current != output {
        let next = g
            .node
            .iter()
            .enumerate()
            .find(|(k, n)| !used[*k] && n.input.contains(&current));
        let Some((k, node)) = next else {
            return Err(format!(
                "nothing computes the output '{output}' from '{current}'"
            ));
        };
        used[k] = true;
        supported(node)?;
        for i in &node.input {
            if *i != current && !i.is_empty() && !constants.contains_key(i) {
                return Err(format!(
                    "{} node '{}' combines two computed tensors ('{current}', '{i}'): only chains of operators on one tensor are supported",
                    node.op_type.as_deref().unwrap_or("?"),
                    node.name.as_deref().unwrap_or("")
                ));
            }
        }
        current = node
            .output
            .first()
            .cloned()
            .ok_or("a node without outputs")?;
        path.push(node);
    }
    if path.is_empty() {
        return Err("the graph computes nothing".into());
    }
    Ok(path)
}

/// The element type of the graph's input (1 float, 11 double).
pub fn input_type(g: &GraphProto) -> Option<i32> {
    g.input
        .first()
        .and_then(|i| i.r#type.as_ref())
        .and_then(|t| t.tensor_type.as_ref())
        .and_then(|t| t.elem_type)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tensor(dims: &[i64], raw: Vec<u8>) -> TensorProto {
        TensorProto {
            dims: dims.to_vec(),
            data_type: Some(data_type::FLOAT),
            name: Some("W".into()),
            raw_data: Some(raw),
            ..Default::default()
        }
    }

    /// Shapes that overflow, exceed the bound or go negative, and raw data of another length
    /// than the shape states, are refused before anything is allocated for their values.
    #[test]
    fn tensor_shapes_are_bounded_before_allocation() {
        let e = tensor_values(&tensor(&[1 << 40, 1 << 40], vec![0; 8])).unwrap_err();
        assert!(e.contains("tensor 'W'") && e.contains("more than"), "{e}");
        let e = tensor_values(&tensor(&[75_000_000], vec![0; 16])).unwrap_err();
        assert!(e.contains("more than 16777216 values"), "{e}");
        let e = tensor_values(&tensor(&[2, -3], vec![0; 8])).unwrap_err();
        assert!(e.contains("negative dimension -3"), "{e}");
        let e = tensor_values(&tensor(&[4], vec![0; 8])).unwrap_err();
        assert!(e.contains("8 bytes of raw data for shape [4]"), "{e}");
        let ok = tensor_values(&tensor(
            &[2],
            [1.5f32, -2.0]
                .iter()
                .flat_map(|v| v.to_le_bytes())
                .collect(),
        ))
        .unwrap();
        assert_eq!(ok.values, [1.5, -2.0]);
    }
}
