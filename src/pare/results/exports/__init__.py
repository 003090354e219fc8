"""A run's results in the field's formats: the Every Eval Ever schema (:mod:`.eee`) and chat-format
conversations for fine-tuning (:mod:`.sft`). Both read a run folder through :mod:`pare.results` only.
"""
