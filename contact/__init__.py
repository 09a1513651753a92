"""Stick-slip-separation contact model of Li, Yao & Wu (2016), Eqs. 4-21.

Never imports the ``fem`` stage: parameters arrive as :class:`rom.params.MotorParams`.
"""
