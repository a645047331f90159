package dev.motionfusion.app.live

import kotlin.math.roundToLong

/** Rounds an angle in degrees to the 0.1° shown on screen, without a "-0.0". */
fun displayDegrees(deg: Double): Double = (deg * 10.0).roundToLong() / 10.0 + 0.0
