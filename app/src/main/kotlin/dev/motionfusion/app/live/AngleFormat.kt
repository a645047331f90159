package dev.motionfusion.app.live

import kotlin.math.roundToLong

/** Rounds an angle in degrees to the 0.1° shown on screen, without a "-0.0". */
fun displayDegrees(deg: Double): Double = (deg * 10.0).roundToLong() / 10.0 + 0.0

/** Like [displayDegrees] for a heading in [0, 360): 359.96° shows as 0.0°, not 360.0°. */
fun displayHeading(deg: Double): Double = displayDegrees(deg).let { if (it >= 360.0) it - 360.0 else it }
