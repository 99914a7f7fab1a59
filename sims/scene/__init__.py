"""CoppeliaSim scenes as data: the scene model, its readers (``.ttt``, ``.simscene.xml``) and the
builder that turns a model into a pybullet world. Loading a scene runs nothing."""
