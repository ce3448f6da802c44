"""keller's files as objects (keller.open): branches and curves (`keller trace`), time series
(`keller evolve`), steady states (`keller solve`) and studies (`keller study`), one module per
kind over what they share (h5: opening, scene, provenance; table; fields: fields and meshes)."""
