"""Teaching at run time: a person's naming of a place applied to a learned model at once (``teach``), where to ask
(``questions``), and utterances recorded by the robot node applied later (``recorded``). A layer above learning
and planning: a teach updates the model and the planner's graph."""
