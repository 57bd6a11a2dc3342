//! See the doc comment on `mod arrays_test` in layer.rs.

use std::path::Path;
use std::process::Command;

use openusd::gf::{self, f16};
use openusd::sdf::{AssetPath, TimeCode, Value};
use serde_json::{Value as Json, json};

use super::{Layer, Samples};

/// Longest array written.
const LONGEST: usize = 40;

/// A spread of 32-bit integers (large, negative, repeated) for element `i` of an array
/// of `n`, so that the integer coding meets every case it has.
fn int(n: usize, i: usize) -> i32 {
    (i as i32).wrapping_mul(-1_640_531_535) ^ (n as i32) ^ ((i % 3) as i32)
}

/// The same for 64 bits.
fn int64(n: usize, i: usize) -> i64 {
    (i as i64).wrapping_mul(-7_046_029_254_386_353_131) ^ (n as i64)
}

/// Exactly representable in half precision.
fn half(n: usize, i: usize) -> f16 {
    f16::from_f32((i as f32 - n as f32 / 2.0) * 0.25)
}

fn float(n: usize, i: usize) -> f32 {
    i as f32 * 1.37 - n as f32
}

fn double(n: usize, i: usize) -> f64 {
    i as f64 * 0.1 + n as f64 / 3.0
}

/// One array type: its USD type name, the value of length `n` and what usd-core must
/// read back.
struct ArrayType {
    name: &'static str,
    make: fn(usize) -> (Value, Json),
}

fn each<T, J: Into<Json>>(n: usize, f: impl Fn(usize) -> (T, J)) -> (Vec<T>, Json) {
    let (values, json): (Vec<T>, Vec<Json>) = (0..n)
        .map(|i| {
            let (value, json) = f(i);
            (value, json.into())
        })
        .unzip();
    (values, Json::Array(json))
}

/// `[f(i, 0), f(i, 1), ... f(i, K-1)]` for a vector of K components.
fn components<T: Copy, const K: usize>(i: usize, f: impl Fn(usize) -> T) -> [T; K] {
    std::array::from_fn(|k| f(i * K + k))
}

fn halves(v: &[f16]) -> Json {
    v.iter().map(|h| h.to_f64()).collect::<Vec<_>>().into()
}

fn floats(v: &[f32]) -> Json {
    v.iter().map(|&x| f64::from(x)).collect::<Vec<_>>().into()
}

macro_rules! vector {
    ($variant:ident, $gf:ty, $k:literal, $f:ident, $json:expr) => {
        |n| {
            let (v, j) = each(n, |i| {
                let c: [_; $k] = components(i, |j| $f(n, j));
                (<$gf>::from(c), $json(&c))
            });
            (Value::$variant(v), j)
        }
    };
}

fn types() -> Vec<ArrayType> {
    fn same<T: Copy + Into<Json>>(c: &[T]) -> Json {
        c.iter().map(|&x| x.into()).collect::<Vec<Json>>().into()
    }
    vec![
        ArrayType {
            name: "bool[]",
            make: |n| {
                let (v, j) = each(n, |i| ((i * n) % 3 == 0, (i * n) % 3 == 0));
                (Value::BoolVec(v), j)
            },
        },
        ArrayType {
            name: "uchar[]",
            make: |n| {
                let (v, j) = each(n, |i| ((i * 37 + n) as u8, (i * 37 + n) as u8));
                (Value::UcharVec(v), j)
            },
        },
        ArrayType {
            name: "int[]",
            make: |n| {
                let (v, j) = each(n, |i| (int(n, i), int(n, i)));
                (Value::IntVec(v), j)
            },
        },
        ArrayType {
            name: "uint[]",
            make: |n| {
                let (v, j) = each(n, |i| (int(n, i) as u32, int(n, i) as u32));
                (Value::UintVec(v), j)
            },
        },
        ArrayType {
            name: "int64[]",
            make: |n| {
                let (v, j) = each(n, |i| (int64(n, i), int64(n, i)));
                (Value::Int64Vec(v), j)
            },
        },
        ArrayType {
            name: "uint64[]",
            make: |n| {
                let (v, j) = each(n, |i| (int64(n, i) as u64, int64(n, i) as u64));
                (Value::Uint64Vec(v), j)
            },
        },
        ArrayType {
            name: "half[]",
            make: |n| {
                let (v, j) = each(n, |i| (half(n, i), half(n, i).to_f64()));
                (Value::HalfVec(v), j)
            },
        },
        ArrayType {
            name: "float[]",
            make: |n| {
                let (v, j) = each(n, |i| (float(n, i), f64::from(float(n, i))));
                (Value::FloatVec(v), j)
            },
        },
        ArrayType {
            name: "double[]",
            make: |n| {
                let (v, j) = each(n, |i| (double(n, i), double(n, i)));
                (Value::DoubleVec(v), j)
            },
        },
        ArrayType {
            name: "timecode[]",
            make: |n| {
                let (v, j) = each(n, |i| (TimeCode(double(n, i)), double(n, i)));
                (Value::TimeCodeVec(v), j)
            },
        },
        ArrayType {
            name: "int2[]",
            make: vector!(Vec2iVec, gf::Vec2i, 2, int, same),
        },
        ArrayType {
            name: "int3[]",
            make: vector!(Vec3iVec, gf::Vec3i, 3, int, same),
        },
        ArrayType {
            name: "int4[]",
            make: vector!(Vec4iVec, gf::Vec4i, 4, int, same),
        },
        ArrayType {
            name: "half2[]",
            make: vector!(Vec2hVec, gf::Vec2h, 2, half, halves),
        },
        ArrayType {
            name: "half3[]",
            make: vector!(Vec3hVec, gf::Vec3h, 3, half, halves),
        },
        ArrayType {
            name: "half4[]",
            make: vector!(Vec4hVec, gf::Vec4h, 4, half, halves),
        },
        ArrayType {
            name: "float2[]",
            make: vector!(Vec2fVec, gf::Vec2f, 2, float, floats),
        },
        ArrayType {
            name: "float3[]",
            make: vector!(Vec3fVec, gf::Vec3f, 3, float, floats),
        },
        ArrayType {
            name: "float4[]",
            make: vector!(Vec4fVec, gf::Vec4f, 4, float, floats),
        },
        ArrayType {
            name: "double2[]",
            make: vector!(Vec2dVec, gf::Vec2d, 2, double, same),
        },
        ArrayType {
            name: "double3[]",
            make: vector!(Vec3dVec, gf::Vec3d, 3, double, same),
        },
        ArrayType {
            name: "double4[]",
            make: vector!(Vec4dVec, gf::Vec4d, 4, double, same),
        },
        ArrayType {
            name: "matrix2d[]",
            make: vector!(Matrix2dVec, gf::Mat2d, 4, double, same),
        },
        ArrayType {
            name: "matrix3d[]",
            make: vector!(Matrix3dVec, gf::Mat3d, 9, double, same),
        },
        ArrayType {
            name: "matrix4d[]",
            make: vector!(Matrix4dVec, gf::Matrix4d, 16, double, same),
        },
        ArrayType {
            name: "quath[]",
            make: |n| {
                let (v, j) = each(n, |i| {
                    let [w, x, y, z]: [f16; 4] = components(i, |j| half(n, j));
                    (gf::Quath { w, x, y, z }, halves(&[w, x, y, z]))
                });
                (Value::QuathVec(v), j)
            },
        },
        ArrayType {
            name: "quatf[]",
            make: |n| {
                let (v, j) = each(n, |i| {
                    let [w, x, y, z]: [f32; 4] = components(i, |j| float(n, j));
                    (gf::Quatf { w, x, y, z }, floats(&[w, x, y, z]))
                });
                (Value::QuatfVec(v), j)
            },
        },
        ArrayType {
            name: "quatd[]",
            make: |n| {
                let (v, j) = each(n, |i| {
                    let [w, x, y, z]: [f64; 4] = components(i, |j| double(n, j));
                    (gf::Quatd { w, x, y, z }, json!([w, x, y, z]))
                });
                (Value::QuatdVec(v), j)
            },
        },
        ArrayType {
            name: "string[]",
            make: |n| {
                let (v, j) = each(n, |i| (format!("s{n}_{i}"), format!("s{n}_{i}")));
                (Value::StringVec(v), j)
            },
        },
        ArrayType {
            name: "token[]",
            make: |n| {
                let (v, j) = each(n, |i| (format!("t{n}_{i}"), format!("t{n}_{i}")));
                (Value::token_vec(v), j)
            },
        },
        ArrayType {
            name: "asset[]",
            make: |n| {
                let (v, j) = each(n, |i| {
                    (
                        AssetPath::new(format!("a{n}_{i}.usd")),
                        format!("a{n}_{i}.usd"),
                    )
                });
                (Value::AssetPathVec(v), j)
            },
        },
    ]
}

/// An attribute name for a type name (`int[]` → `a_int`).
fn attribute(type_name: &str) -> String {
    format!("a_{}", type_name.trim_end_matches("[]"))
}

#[test]
fn every_array_type_at_every_length_reads_back_in_usd_core() {
    // The layer: prim /L{n} holds each type's array of length n as its default;
    // prim /Samples holds, for each type, the array of length n at time code n.
    let types = types();
    let mut layer = Layer::new(vec![]);
    let mut expected = serde_json::Map::new();
    let mut samples: Vec<Samples> = types.iter().map(|_| Vec::new()).collect();
    for n in 0..=LONGEST {
        let prim = layer.def("/", &format!("L{n}"), "Scope").unwrap();
        for (array, samples) in types.iter().zip(&mut samples) {
            let (value, json) = (array.make)(n);
            let name = attribute(array.name);
            layer
                .attribute(&prim, &name, array.name, false, value.clone(), vec![])
                .unwrap();
            samples.push((n as f64, value));
            expected.insert(format!("{prim}.{name}"), json.clone());
            expected.insert(format!("/Samples.{name}@{n}"), json);
        }
    }
    let prim = layer.def("/", "Samples", "Scope").unwrap();
    for (array, samples) in types.iter().zip(samples) {
        layer
            .animated(&prim, &attribute(array.name), array.name, samples, vec![])
            .unwrap();
    }
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("arrays.usdc");
    std::fs::write(&file, layer.into_usdc().unwrap()).unwrap();

    let scripts = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scripts/dcc");
    let venv = Command::new("bash")
        .arg(scripts.join("venv.sh"))
        .output()
        .unwrap();
    if venv.status.code() == Some(77) {
        eprintln!(
            "\n*** SKIPPED the usd-core check: {} ***\n",
            String::from_utf8_lossy(&venv.stderr)
        );
        return;
    }
    assert!(
        venv.status.success(),
        "{}",
        String::from_utf8_lossy(&venv.stderr)
    );
    let python = String::from_utf8(venv.stdout).unwrap();
    let read = Command::new(python.trim())
        .arg(scripts.join("usdc_defaults.py"))
        .arg(&file)
        .output()
        .unwrap();
    assert!(
        read.status.success(),
        "{}",
        String::from_utf8_lossy(&read.stderr)
    );
    let read: serde_json::Map<String, Json> = serde_json::from_slice(&read.stdout).unwrap();
    let mut wrong = Vec::new();
    for (key, want) in &expected {
        match read.get(key) {
            Some(got) if got == want => {}
            got => wrong.push(format!("{key}: wrote {want}, usd-core read {got:?}")),
        }
    }
    assert!(
        wrong.is_empty(),
        "{} of {} arrays differ, e.g.\n{}",
        wrong.len(),
        expected.len(),
        wrong[..wrong.len().min(20)].join("\n")
    );
    assert_eq!(
        read.len(),
        expected.len(),
        "usd-core read attributes we did not write"
    );
}
