//! JSON Schemas (schema encoding `jsonschema`) of every channel.
//!
//! The two Foxglove schemas follow Foxglove's published JSON schemas for
//! `foxglove.FrameTransform` and `foxglove.SceneUpdate` (same field names, types and
//! enum values), so Foxglove and Lichtblick decode the messages with their built-in
//! 3D panel and no extension. The `rsts.*` schemas describe our numeric series so that
//! the Plot panel lists their fields.

/// Schema name of the body-orientation transforms.
pub const FRAME_TRANSFORM_NAME: &str = "foxglove.FrameTransform";
/// Schema name of the hodograph scene updates.
pub const SCENE_UPDATE_NAME: &str = "foxglove.SceneUpdate";
/// Schema name of `/exact/state` and `/integrated/state`.
pub const BODY_STATE_NAME: &str = "rsts.BodyState";
/// Schema name of `/errors`.
pub const ERRORS_NAME: &str = "rsts.Errors";
/// Schema name of `/metadata`.
pub const METADATA_NAME: &str = "rsts.Metadata";

/// `foxglove.FrameTransform`.
pub const FRAME_TRANSFORM: &str = r#"{
  "title": "foxglove.FrameTransform",
  "description": "A transform between two reference frames in 3D space",
  "type": "object",
  "properties": {
    "timestamp": {
      "type": "object", "title": "time",
      "properties": {
        "sec": {"type": "integer", "minimum": 0},
        "nsec": {"type": "integer", "minimum": 0, "maximum": 999999999}
      },
      "description": "Timestamp of transform"
    },
    "parent_frame_id": {"type": "string", "description": "Name of the parent frame"},
    "child_frame_id": {"type": "string", "description": "Name of the child frame"},
    "translation": {
      "title": "foxglove.Vector3", "type": "object",
      "description": "Translation component of the transform",
      "properties": {
        "x": {"type": "number", "description": "x coordinate length"},
        "y": {"type": "number", "description": "y coordinate length"},
        "z": {"type": "number", "description": "z coordinate length"}
      }
    },
    "rotation": {
      "title": "foxglove.Quaternion", "type": "object",
      "description": "Rotation component of the transform",
      "properties": {
        "x": {"type": "number", "description": "x value"},
        "y": {"type": "number", "description": "y value"},
        "z": {"type": "number", "description": "z value"},
        "w": {"type": "number", "description": "w value"}
      }
    }
  }
}"#;

/// `foxglove.SceneUpdate`, every sub-schema inlined (no `$ref`: Foxglove's JSON-schema
/// parser does not resolve references), as in Foxglove's published schema.
pub const SCENE_UPDATE: &str = r##"{
 "title": "foxglove.SceneUpdate",
 "description": "An update to the entities displayed in a 3D scene",
 "type": "object",
 "properties": {
  "deletions": {
   "type": "array",
   "items": {
    "title": "foxglove.SceneEntityDeletion",
    "type": "object",
    "properties": {
     "timestamp": {
      "type": "object",
      "title": "time",
      "properties": {
       "sec": {
        "type": "integer",
        "minimum": 0
       },
       "nsec": {
        "type": "integer",
        "minimum": 0,
        "maximum": 999999999
       }
      }
     },
     "type": {
      "title": "foxglove.SceneEntityDeletionType",
      "oneOf": [
       {
        "title": "MATCHING_ID",
        "const": 0
       },
       {
        "title": "ALL",
        "const": 1
       }
      ]
     },
     "id": {
      "type": "string"
     }
    }
   }
  },
  "entities": {
   "type": "array",
   "items": {
    "title": "foxglove.SceneEntity",
    "type": "object",
    "properties": {
     "timestamp": {
      "type": "object",
      "title": "time",
      "properties": {
       "sec": {
        "type": "integer",
        "minimum": 0
       },
       "nsec": {
        "type": "integer",
        "minimum": 0,
        "maximum": 999999999
       }
      }
     },
     "frame_id": {
      "type": "string"
     },
     "id": {
      "type": "string"
     },
     "lifetime": {
      "type": "object",
      "title": "duration",
      "properties": {
       "sec": {
        "type": "integer"
       },
       "nsec": {
        "type": "integer",
        "minimum": 0,
        "maximum": 999999999
       }
      }
     },
     "frame_locked": {
      "type": "boolean"
     },
     "metadata": {
      "type": "array",
      "items": {
       "title": "foxglove.KeyValuePair",
       "type": "object",
       "properties": {
        "key": {
         "type": "string"
        },
        "value": {
         "type": "string"
        }
       }
      }
     },
     "arrows": {
      "type": "array",
      "items": {
       "title": "foxglove.ArrowPrimitive",
       "type": "object",
       "properties": {
        "pose": {
         "title": "foxglove.Pose",
         "type": "object",
         "properties": {
          "position": {
           "title": "foxglove.Vector3",
           "type": "object",
           "properties": {
            "x": {
             "type": "number"
            },
            "y": {
             "type": "number"
            },
            "z": {
             "type": "number"
            }
           }
          },
          "orientation": {
           "title": "foxglove.Quaternion",
           "type": "object",
           "properties": {
            "x": {
             "type": "number"
            },
            "y": {
             "type": "number"
            },
            "z": {
             "type": "number"
            },
            "w": {
             "type": "number"
            }
           }
          }
         }
        },
        "shaft_length": {
         "type": "number"
        },
        "shaft_diameter": {
         "type": "number"
        },
        "head_length": {
         "type": "number"
        },
        "head_diameter": {
         "type": "number"
        },
        "color": {
         "title": "foxglove.Color",
         "type": "object",
         "properties": {
          "r": {
           "type": "number"
          },
          "g": {
           "type": "number"
          },
          "b": {
           "type": "number"
          },
          "a": {
           "type": "number"
          }
         }
        }
       }
      }
     },
     "cubes": {
      "type": "array",
      "items": {
       "title": "foxglove.CubePrimitive",
       "type": "object",
       "properties": {
        "pose": {
         "title": "foxglove.Pose",
         "type": "object",
         "properties": {
          "position": {
           "title": "foxglove.Vector3",
           "type": "object",
           "properties": {
            "x": {
             "type": "number"
            },
            "y": {
             "type": "number"
            },
            "z": {
             "type": "number"
            }
           }
          },
          "orientation": {
           "title": "foxglove.Quaternion",
           "type": "object",
           "properties": {
            "x": {
             "type": "number"
            },
            "y": {
             "type": "number"
            },
            "z": {
             "type": "number"
            },
            "w": {
             "type": "number"
            }
           }
          }
         }
        },
        "size": {
         "title": "foxglove.Vector3",
         "type": "object",
         "properties": {
          "x": {
           "type": "number"
          },
          "y": {
           "type": "number"
          },
          "z": {
           "type": "number"
          }
         }
        },
        "color": {
         "title": "foxglove.Color",
         "type": "object",
         "properties": {
          "r": {
           "type": "number"
          },
          "g": {
           "type": "number"
          },
          "b": {
           "type": "number"
          },
          "a": {
           "type": "number"
          }
         }
        }
       }
      }
     },
     "spheres": {
      "type": "array",
      "items": {
       "title": "foxglove.SpherePrimitive",
       "type": "object",
       "properties": {
        "pose": {
         "title": "foxglove.Pose",
         "type": "object",
         "properties": {
          "position": {
           "title": "foxglove.Vector3",
           "type": "object",
           "properties": {
            "x": {
             "type": "number"
            },
            "y": {
             "type": "number"
            },
            "z": {
             "type": "number"
            }
           }
          },
          "orientation": {
           "title": "foxglove.Quaternion",
           "type": "object",
           "properties": {
            "x": {
             "type": "number"
            },
            "y": {
             "type": "number"
            },
            "z": {
             "type": "number"
            },
            "w": {
             "type": "number"
            }
           }
          }
         }
        },
        "size": {
         "title": "foxglove.Vector3",
         "type": "object",
         "properties": {
          "x": {
           "type": "number"
          },
          "y": {
           "type": "number"
          },
          "z": {
           "type": "number"
          }
         }
        },
        "color": {
         "title": "foxglove.Color",
         "type": "object",
         "properties": {
          "r": {
           "type": "number"
          },
          "g": {
           "type": "number"
          },
          "b": {
           "type": "number"
          },
          "a": {
           "type": "number"
          }
         }
        }
       }
      }
     },
     "cylinders": {
      "type": "array",
      "items": {
       "title": "foxglove.CylinderPrimitive",
       "type": "object",
       "properties": {
        "pose": {
         "title": "foxglove.Pose",
         "type": "object",
         "properties": {
          "position": {
           "title": "foxglove.Vector3",
           "type": "object",
           "properties": {
            "x": {
             "type": "number"
            },
            "y": {
             "type": "number"
            },
            "z": {
             "type": "number"
            }
           }
          },
          "orientation": {
           "title": "foxglove.Quaternion",
           "type": "object",
           "properties": {
            "x": {
             "type": "number"
            },
            "y": {
             "type": "number"
            },
            "z": {
             "type": "number"
            },
            "w": {
             "type": "number"
            }
           }
          }
         }
        },
        "size": {
         "title": "foxglove.Vector3",
         "type": "object",
         "properties": {
          "x": {
           "type": "number"
          },
          "y": {
           "type": "number"
          },
          "z": {
           "type": "number"
          }
         }
        },
        "bottom_scale": {
         "type": "number"
        },
        "top_scale": {
         "type": "number"
        },
        "color": {
         "title": "foxglove.Color",
         "type": "object",
         "properties": {
          "r": {
           "type": "number"
          },
          "g": {
           "type": "number"
          },
          "b": {
           "type": "number"
          },
          "a": {
           "type": "number"
          }
         }
        }
       }
      }
     },
     "lines": {
      "type": "array",
      "items": {
       "title": "foxglove.LinePrimitive",
       "type": "object",
       "properties": {
        "type": {
         "title": "foxglove.LineType",
         "description": "An enumeration indicating how input points should be interpreted to create lines",
         "oneOf": [
          {
           "title": "LINE_STRIP",
           "const": 0,
           "description": "Connected line segments: 0-1, 1-2, ..., (n-1)-n"
          },
          {
           "title": "LINE_LOOP",
           "const": 1,
           "description": "Closed polygon: 0-1, 1-2, ..., (n-1)-n, n-0"
          },
          {
           "title": "LINE_LIST",
           "const": 2,
           "description": "Individual line segments: 0-1, 2-3, 4-5, ..."
          }
         ]
        },
        "pose": {
         "title": "foxglove.Pose",
         "type": "object",
         "properties": {
          "position": {
           "title": "foxglove.Vector3",
           "type": "object",
           "properties": {
            "x": {
             "type": "number"
            },
            "y": {
             "type": "number"
            },
            "z": {
             "type": "number"
            }
           }
          },
          "orientation": {
           "title": "foxglove.Quaternion",
           "type": "object",
           "properties": {
            "x": {
             "type": "number"
            },
            "y": {
             "type": "number"
            },
            "z": {
             "type": "number"
            },
            "w": {
             "type": "number"
            }
           }
          }
         }
        },
        "thickness": {
         "type": "number",
         "minimum": 0
        },
        "scale_invariant": {
         "type": "boolean"
        },
        "points": {
         "type": "array",
         "items": {
          "title": "foxglove.Point3",
          "type": "object",
          "properties": {
           "x": {
            "type": "number"
           },
           "y": {
            "type": "number"
           },
           "z": {
            "type": "number"
           }
          }
         }
        },
        "color": {
         "title": "foxglove.Color",
         "type": "object",
         "properties": {
          "r": {
           "type": "number"
          },
          "g": {
           "type": "number"
          },
          "b": {
           "type": "number"
          },
          "a": {
           "type": "number"
          }
         }
        },
        "colors": {
         "type": "array",
         "items": {
          "title": "foxglove.Color",
          "type": "object",
          "properties": {
           "r": {
            "type": "number"
           },
           "g": {
            "type": "number"
           },
           "b": {
            "type": "number"
           },
           "a": {
            "type": "number"
           }
          }
         }
        },
        "indices": {
         "type": "array",
         "items": {
          "type": "integer",
          "minimum": 0
         }
        }
       }
      }
     },
     "triangles": {
      "type": "array",
      "items": {
       "title": "foxglove.TriangleListPrimitive",
       "type": "object",
       "properties": {
        "pose": {
         "title": "foxglove.Pose",
         "type": "object",
         "properties": {
          "position": {
           "title": "foxglove.Vector3",
           "type": "object",
           "properties": {
            "x": {
             "type": "number"
            },
            "y": {
             "type": "number"
            },
            "z": {
             "type": "number"
            }
           }
          },
          "orientation": {
           "title": "foxglove.Quaternion",
           "type": "object",
           "properties": {
            "x": {
             "type": "number"
            },
            "y": {
             "type": "number"
            },
            "z": {
             "type": "number"
            },
            "w": {
             "type": "number"
            }
           }
          }
         }
        },
        "points": {
         "type": "array",
         "items": {
          "title": "foxglove.Point3",
          "type": "object",
          "properties": {
           "x": {
            "type": "number"
           },
           "y": {
            "type": "number"
           },
           "z": {
            "type": "number"
           }
          }
         }
        },
        "color": {
         "title": "foxglove.Color",
         "type": "object",
         "properties": {
          "r": {
           "type": "number"
          },
          "g": {
           "type": "number"
          },
          "b": {
           "type": "number"
          },
          "a": {
           "type": "number"
          }
         }
        },
        "colors": {
         "type": "array",
         "items": {
          "title": "foxglove.Color",
          "type": "object",
          "properties": {
           "r": {
            "type": "number"
           },
           "g": {
            "type": "number"
           },
           "b": {
            "type": "number"
           },
           "a": {
            "type": "number"
           }
          }
         }
        },
        "indices": {
         "type": "array",
         "items": {
          "type": "integer",
          "minimum": 0
         }
        }
       }
      }
     },
     "texts": {
      "type": "array",
      "items": {
       "title": "foxglove.TextPrimitive",
       "type": "object",
       "properties": {
        "pose": {
         "title": "foxglove.Pose",
         "type": "object",
         "properties": {
          "position": {
           "title": "foxglove.Vector3",
           "type": "object",
           "properties": {
            "x": {
             "type": "number"
            },
            "y": {
             "type": "number"
            },
            "z": {
             "type": "number"
            }
           }
          },
          "orientation": {
           "title": "foxglove.Quaternion",
           "type": "object",
           "properties": {
            "x": {
             "type": "number"
            },
            "y": {
             "type": "number"
            },
            "z": {
             "type": "number"
            },
            "w": {
             "type": "number"
            }
           }
          }
         }
        },
        "billboard": {
         "type": "boolean"
        },
        "font_size": {
         "type": "number"
        },
        "scale_invariant": {
         "type": "boolean"
        },
        "color": {
         "title": "foxglove.Color",
         "type": "object",
         "properties": {
          "r": {
           "type": "number"
          },
          "g": {
           "type": "number"
          },
          "b": {
           "type": "number"
          },
          "a": {
           "type": "number"
          }
         }
        },
        "text": {
         "type": "string"
        }
       }
      }
     },
     "models": {
      "type": "array",
      "items": {
       "title": "foxglove.ModelPrimitive",
       "type": "object",
       "properties": {
        "pose": {
         "title": "foxglove.Pose",
         "type": "object",
         "properties": {
          "position": {
           "title": "foxglove.Vector3",
           "type": "object",
           "properties": {
            "x": {
             "type": "number"
            },
            "y": {
             "type": "number"
            },
            "z": {
             "type": "number"
            }
           }
          },
          "orientation": {
           "title": "foxglove.Quaternion",
           "type": "object",
           "properties": {
            "x": {
             "type": "number"
            },
            "y": {
             "type": "number"
            },
            "z": {
             "type": "number"
            },
            "w": {
             "type": "number"
            }
           }
          }
         }
        },
        "scale": {
         "title": "foxglove.Vector3",
         "type": "object",
         "properties": {
          "x": {
           "type": "number"
          },
          "y": {
           "type": "number"
          },
          "z": {
           "type": "number"
          }
         }
        },
        "color": {
         "title": "foxglove.Color",
         "type": "object",
         "properties": {
          "r": {
           "type": "number"
          },
          "g": {
           "type": "number"
          },
          "b": {
           "type": "number"
          },
          "a": {
           "type": "number"
          }
         }
        },
        "override_color": {
         "type": "boolean"
        },
        "url": {
         "type": "string"
        },
        "media_type": {
         "type": "string"
        },
        "data": {
         "type": "string",
         "contentEncoding": "base64"
        }
       }
      }
     }
    }
   }
  }
 }
}"##;

/// `rsts.BodyState`: one body state of the exact or the integrated motion.
pub const BODY_STATE: &str = r#"{
  "title": "rsts.BodyState",
  "description": "State of the rigid body at motion time t. Q has rows alpha, beta, gamma (fixed axes in the body frame), Omega = Q omega.",
  "type": "object",
  "properties": {
    "t": {"type": "number", "description": "motion time (s)"},
    "alpha": {"type": "array", "description": "row 1 of Q: the fixed axis alpha in the body frame", "items": {"type": "number"}, "minItems": 3, "maxItems": 3},
    "beta": {"type": "array", "description": "row 2 of Q: the fixed axis beta in the body frame", "items": {"type": "number"}, "minItems": 3, "maxItems": 3},
    "gamma": {"type": "array", "description": "row 3 of Q: the fixed axis gamma in the body frame", "items": {"type": "number"}, "minItems": 3, "maxItems": 3},
    "quaternion": {"type": "object", "description": "attitude quaternion (body to world) from Q", "properties": {"x": {"type": "number"}, "y": {"type": "number"}, "z": {"type": "number"}, "w": {"type": "number"}}},
    "omega": {"type": "array", "description": "angular velocity, body frame", "items": {"type": "number"}, "minItems": 3, "maxItems": 3},
    "omega_fixed": {"type": "array", "description": "angular velocity, fixed frame (Q omega)", "items": {"type": "number"}, "minItems": 3, "maxItems": 3},
    "h": {"type": "number", "description": "energy integral"},
    "k": {"type": "number", "description": "second (Kowalevski-type) integral"},
    "g": {"type": "number", "description": "third integral"}
  }
}"#;

/// `rsts.Errors`: differences between the integrated and the exact motion.
pub const ERRORS: &str = r#"{
  "title": "rsts.Errors",
  "description": "Errors of the integrated motion against the exact one at motion time t",
  "type": "object",
  "properties": {
    "t": {"type": "number", "description": "motion time (s)"},
    "state_error": {"type": "number", "description": "norm of the state difference"},
    "orientation_error": {"type": "number", "description": "angle or norm of the orientation difference"},
    "drift_h": {"type": "number", "description": "drift of the integral h along the integrated motion"},
    "drift_k": {"type": "number", "description": "drift of the integral k along the integrated motion"},
    "drift_g": {"type": "number", "description": "drift of the integral g along the integrated motion"},
    "constraint_drift": {"type": "number", "description": "drift of the geometric constraints (orthonormality of Q)"},
    "off_n": {"type": "number", "description": "harness-defined off-manifold measure"}
  }
}"#;

/// `rsts.Metadata`: the comparison's case, integrator configuration and software version.
pub const METADATA: &str = r#"{
  "title": "rsts.Metadata",
  "description": "Case, integrator configuration and software version of one comparison",
  "type": "object",
  "properties": {
    "software_version": {"type": "string"},
    "case": {"type": "object", "description": "the case: a, b, m, h, torus, phases, t_end, samples", "properties": {}},
    "integrator": {"type": "object", "description": "method, rtol, atol, digits", "properties": {}}
  }
}"#;
