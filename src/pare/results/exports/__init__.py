"""A run's results in the field's formats: the Every Eval Ever schema (:mod:`.eee`), Inspect's log format
(:mod:`.inspect_log`) and chat-format conversations for fine-tuning (:mod:`.sft`). Each reads a run folder
through :mod:`pare.results` only, and trajectories through :mod:`.episodes`.
"""
