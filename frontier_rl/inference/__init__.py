"""Running a trained model without the training stack: model files read with every check an
untrusted file needs (:mod:`~frontier_rl.inference.model_file`), the networks in plain torch
(:mod:`~frontier_rl.inference.networks`) and a model as an actor that answers an observation
(:mod:`~frontier_rl.inference.actor`). Needs torch; not Gymnasium, not Stable-Baselines3."""
