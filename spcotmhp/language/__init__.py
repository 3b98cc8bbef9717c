"""Language: what people say, as text the planner and the learner can use.

:mod:`~spcotmhp.language.text` normalises text (NFKC width folding, case folding) and cuts it into words
(English word units; Japanese by the morphological analyser janome when the text has no spaces);
:mod:`~spcotmhp.language.reading` reads an instruction with the declarative grammar of its language
(``grammars/<lang>.lark`` and the word classes of ``grammars/<lang>.json``) into its meaning
(:mod:`~spcotmhp.language.meaning`): the places to visit in order, to avoid and not to end in, with the relations
that pick one of several instances, a speed and waits.
"""
