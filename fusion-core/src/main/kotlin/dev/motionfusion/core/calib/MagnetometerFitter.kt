/*
 * Hard- and soft-iron calibration of the magnetometer (device frame, µT): the raw readings of
 * a phone turned through many orientations lie on an ellipsoid; its fit maps them onto a sphere.
 */
package dev.motionfusion.core.calib

import dev.motionfusion.core.event.SessionStream
import kotlin.math.sqrt

/**
 * Collects magnetometer samples ([add]) and fits them ([fit]). Memory is bounded: beyond
 * [CalibrationSettings.maxMagSamples] every second kept sample is dropped and the stride doubles,
 * so a long recording is thinned evenly.
 */
public class MagnetometerFitter(private val settings: CalibrationSettings = CalibrationSettings(), private val stream: SessionStream = SessionStream.MAGNETOMETER_UNCALIBRATED) {
    private var xyz = DoubleArray(3 * 1024)
    private var kept = 0
    private var stride = 1L
    private var seen = 0L

    /** Adds one reading, µT; non-finite readings are skipped. */
    public fun add(x: Double, y: Double, z: Double) {
        if (!(x.isFinite() && y.isFinite() && z.isFinite())) return
        val k = seen++
        if (k % stride != 0L) return
        if (kept == settings.maxMagSamples) {
            for (i in 0 until kept / 2) {
                xyz[3 * i] = xyz[6 * i]; xyz[3 * i + 1] = xyz[6 * i + 1]; xyz[3 * i + 2] = xyz[6 * i + 2]
            }
            kept /= 2
            stride *= 2
            if (k % stride != 0L) return
        }
        if (3 * kept + 3 > xyz.size) xyz = xyz.copyOf(minOf(2 * xyz.size, 3 * settings.maxMagSamples))
        xyz[3 * kept] = x; xyz[3 * kept + 1] = y; xyz[3 * kept + 2] = z
        kept++
    }

    /** Readings added so far (including those thinned out). */
    public val samples: Long get() = seen

    /**
     * The directions covered so far, for a live picture while the phone is being turned: the
     * kept readings corrected by the ellipsoid fitted to them now (the sphere model while the
     * configured one is not determined or gives an implausible field), so the cells are those
     * [fit] would count. Empty while no centre can be located. Costs a fit over the kept
     * readings: call it a few times a second, not per reading.
     */
    public fun coverage(): DirectionCoverage {
        val out = DirectionCoverage()
        if (kept < 10) return out
        val e = listOf(settings.magModel, EllipsoidModel.SPHERE).distinct().firstNotNullOfOrNull { model ->
            EllipsoidFit.fit(xyz, kept, model)?.takeIf { it.meanRadius in MIN_FIELD_UT..MAX_FIELD_UT }
        } ?: return out
        val c = e.correction(e.meanRadius)
        val v = DoubleArray(3)
        for (i in 0 until kept) {
            v[0] = xyz[3 * i]; v[1] = xyz[3 * i + 1]; v[2] = xyz[3 * i + 2]
            c.applyInPlace(v)
            out.add(v[0], v[1], v[2])
        }
        return out
    }

    /** Fits the ellipsoid; refused when the directions cover too little of the sphere or the fit is poor. */
    public fun fit(): Fit<MagnetometerCalibration> {
        if (kept < 100) return Fit.Refused("only $kept magnetometer samples; turn the phone through many orientations for at least 30 s", RefusalKind.FEW_SAMPLES, listOf(kept.toDouble()))
        val e = EllipsoidFit.fit(xyz, kept, settings.magModel)
            ?: return Fit.Refused("the readings do not lie on an ellipsoid (too few directions, or a disturbed field)", RefusalKind.NO_ELLIPSOID)
        val radius = e.meanRadius
        val c = e.correction(radius)
        val coverage = DirectionCoverage()
        val v = DoubleArray(3)
        val before = Moments()
        val after = Moments()
        var sq = 0.0
        for (i in 0 until kept) {
            before.add(sqrt(xyz[3 * i] * xyz[3 * i] + xyz[3 * i + 1] * xyz[3 * i + 1] + xyz[3 * i + 2] * xyz[3 * i + 2]))
            v[0] = xyz[3 * i]; v[1] = xyz[3 * i + 1]; v[2] = xyz[3 * i + 2]
            c.applyInPlace(v)
            coverage.add(v[0], v[1], v[2])
            val m = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
            after.add(m)
            sq += (m - radius) * (m - radius)
        }
        val residual = sqrt(sq / kept)
        if (radius < MIN_FIELD_UT || radius > MAX_FIELD_UT) {
            return Fit.Refused(
                "the readings cover too few directions to locate the centre of the field (the fit gives %.1f µT, outside %.0f–%.0f µT): turn the phone through more orientations (figure eights, all faces up)"
                    .format(java.util.Locale.ROOT, radius, MIN_FIELD_UT, MAX_FIELD_UT),
                RefusalKind.FIELD_OUT_OF_RANGE, listOf(radius, MIN_FIELD_UT, MAX_FIELD_UT),
            )
        }
        val result = MagnetometerCalibration(c, stream, settings.magModel, radius, residual, coverage.fraction, seen, before.std, after.std)
        if (coverage.fraction < settings.minCoverage) {
            return Fit.Refused(
                "the field directions cover %.0f %% of the sphere (at least %.0f %% needed): turn the phone through more orientations (figure eights, all faces up)"
                    .format(java.util.Locale.ROOT, 100 * coverage.fraction, 100 * settings.minCoverage),
                RefusalKind.FEW_DIRECTIONS, listOf(100 * coverage.fraction, 100 * settings.minCoverage),
            )
        }
        if (residual > settings.maxResidualFraction * radius) {
            return Fit.Refused("residual %.2f µT is over %.0f %% of the field (%.1f µT): the field was disturbed during the recording"
                .format(java.util.Locale.ROOT, residual, 100 * settings.maxResidualFraction, radius),
                RefusalKind.DISTURBED, listOf(residual, 100 * settings.maxResidualFraction, radius))
        }
        return Fit.Done(result)
    }
}

/** Plausible magnitudes of a fitted field, µT: the earth's is 22–67 µT, soft iron changes it by tens of percent at most. */
internal const val MIN_FIELD_UT = 10.0
internal const val MAX_FIELD_UT = 200.0

/** Running mean and standard deviation (Welford). */
internal class Moments {
    var n = 0L
        private set
    var mean = 0.0
        private set
    private var m2 = 0.0

    fun add(x: Double) {
        n++
        val d = x - mean
        mean += d / n
        m2 += d * (x - mean)
    }

    val std: Double get() = if (n > 1) sqrt(m2 / (n - 1)) else Double.NaN
}
