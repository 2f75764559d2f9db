"""A running container seen and changed from another process: its management interface
(:mod:`.management`, with holds in :mod:`.holds`), a new model applied atomically with rollback
(:mod:`.apply_update`, its steps in :mod:`.update_steps`, the package's classes read afresh in
:mod:`.reloading`), its observer interface for watchers (:mod:`.observer`), and the operations
without code a container lists at start (:mod:`.code_check`)."""
