"""Pictures of maps, learned places and plans (matplotlib, Agg backend): :mod:`spcotmhp.viz.draw` (map, place
ellipses, Figure 3 edges, paths; the framed CLI figure and the georeferenced service image),
:mod:`spcotmhp.viz.labels` (the planner's place labels, placed without overlaps) and :mod:`spcotmhp.viz.plan`
(the picture of a plan)."""
