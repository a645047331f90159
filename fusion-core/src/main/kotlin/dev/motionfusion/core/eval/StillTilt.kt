package dev.motionfusion.core.eval

import dev.motionfusion.core.STANDARD_GRAVITY
import dev.motionfusion.core.replay.ErrorStatistics
import dev.motionfusion.core.unitQuaternionUp
import kotlin.math.abs
import kotlin.math.acos
import kotlin.math.sqrt

/**
 * The tilt check for recordings without ground truth: the angle between an orientation's up (ENU
 * z in the device frame) and the measured specific force, in degrees, on samples chosen from the
 * sensor readings alone, so that any two filters given the same rows are scored on the same
 * samples. Feed it every row a filter stepped on, in order ([add]); rows without an accelerometer
 * reading or without an orientation are skipped, but still count for the times below.
 *
 * - [still]: the still samples: at least [SETTLE_S] after the first row; for at least [HOLD_S]
 *   without interruption, |ω| < [MAX_RATE] rad/s, ||a| − g| < [MAX_FORCE_ERROR] m/s² (g =
 *   9.80665) and the accelerometer changing by less than [MAX_FORCE_STEP] m/s² from one row to
 *   the next. There the specific force is gravity alone and the angle is the tilt error.
 * - [afterMotion]: the samples with [fromS] ≤ t < [toS] (t as the rows give it) and
 *   ||a| − g| < [MAX_FORCE_ERROR] m/s², still or not: in the seconds after violent motion this
 *   bounds the tilt error from above (linear acceleration is in the angle). Empty without a window.
 *
 * The figure of either is its median ([ErrorStatistics.percentile] 0.5, to 0.01°).
 */
public class StillTilt @JvmOverloads constructor(public val fromS: Double = Double.NaN, public val toS: Double = Double.NaN) {
    public val still: ErrorStatistics = ErrorStatistics()
    public val afterMotion: ErrorStatistics = ErrorStatistics()
    private var firstT = Double.NaN
    private var prevT = Double.NaN
    private val prevA = doubleArrayOf(Double.NaN, Double.NaN, Double.NaN)
    private var stillFor = 0.0

/** One row: time (s), gyroscope (rad/s), specific force (m/s²), orientation [w, x, y, z] sensor → ENU (NaN when none). */
    public fun add(timeS: Double, angularVelocity: DoubleArray, specificForce: DoubleArray, orientation: DoubleArray) {
        val a = specificForce
        val n = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])
        if (!n.isFinite()) return
        if (firstT.isNaN()) firstT = timeS
        val g = angularVelocity
        val rate = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2])
        val step = sqrt((0 until 3).sumOf { (a[it] - prevA[it]) * (a[it] - prevA[it]) })
        val dt = timeS - prevT
        val steady = abs(n - STANDARD_GRAVITY) < MAX_FORCE_ERROR && rate < MAX_RATE && step < MAX_FORCE_STEP
        stillFor = if (steady && dt.isFinite() && dt >= 0) stillFor + dt else 0.0
        prevT = timeS
        a.copyInto(prevA)
        val deg = unitQuaternionUp(orientation, 0) { ux, uy, uz -> Math.toDegrees(acos(((ux * a[0] + uy * a[1] + uz * a[2]) / n).coerceIn(-1.0, 1.0))) }
        if (!deg.isFinite()) return
        if (timeS >= fromS && timeS < toS && abs(n - STANDARD_GRAVITY) < MAX_FORCE_ERROR) afterMotion.add(deg)
        if (stillFor >= HOLD_S && timeS - firstT >= SETTLE_S) still.add(deg)
    }
}

/** Seconds from the first row before any sample counts as still (the filters settle). */
private const val SETTLE_S: Double = 2.0

/** Seconds a still stretch must have lasted before its samples count. */
private const val HOLD_S: Double = 0.5

/** Largest gyroscope magnitude of a still sample, rad/s. */
private const val MAX_RATE: Double = 0.2

/** Largest distance of |a| from standard gravity, m/s². */
private const val MAX_FORCE_ERROR: Double = 0.3

/** Largest change of the accelerometer reading from the previous row, m/s². */
private const val MAX_FORCE_STEP: Double = 0.5
    
