"""Python shared by Speculum's tools (tools/make_scenes.py and modules/probes/tools): one glTF
reader, one ray caster, one table of the extensions' enum names, so the generator, its checks and
the placement tool cannot drift apart on what a file means."""
