package dev.motionfusion.core.calib

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulationSettings
import dev.motionfusion.core.sim.TimeWindow
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import kotlin.math.PI
import kotlin.math.abs
import kotlin.math.cbrt
import kotlin.random.Random

/**
 * Recovery of known sensor errors from the motion simulator. The bounds are the targets stated
 * in docs/CALIBRATION.md; the recovered errors are printed for the record.
 */
class CalibrationFitTest {
    private val softIron = Matrix3.symmetric(1.15, 0.9, 1.05, 0.06, -0.04, 0.08)
    private val hardIron = Vector3(35.0, -20.0, 60.0)

    private fun turning(angularRate: Double, durationS: Double, seed: Long = 3L) = SimulationSettings(
        seed = seed, rateHz = 100.0, durationS = durationS, angularRate = angularRate, magNoise = 0.4,
        magSoftIron = softIron, hardIron = hardIron, hardIronWindow = TimeWindow(0.0, durationS + 1.0),
    )

    private fun magnetometerFit(s: SimulationSettings, settings: CalibrationSettings = CalibrationSettings()): Fit<MagnetometerCalibration> {
        val f = MagnetometerFitter(settings, SessionStream.MAGNETOMETER)
        MotionSimulator(s).forEach { f.add(it.mag.x, it.mag.y, it.mag.z) }
        return f.fit()
    }

    @Test
    fun `symmetric eigen-decomposition reconstructs the matrix`() {
        val r = Random(5)
        repeat(200) {
            val a = Matrix3.symmetric(r.nextDouble(-3.0, 3.0), r.nextDouble(-3.0, 3.0), r.nextDouble(-3.0, 3.0), r.nextDouble(-3.0, 3.0), r.nextDouble(-3.0, 3.0), r.nextDouble(-3.0, 3.0))
            val e = SymmetricEigen(a)
            assertTrue(e.map { it }.maxDifference(a) < 1e-12, "reconstruction of $a")
            val spd = a * a.transpose() + Matrix3.IDENTITY
            val root = SymmetricEigen(spd).map { kotlin.math.sqrt(it) }
            assertTrue((root * root).maxDifference(spd) < 1e-10)
            assertTrue((spd * spd.inverse()).maxDifference(Matrix3.IDENTITY) < 1e-12)
        }
    }

    @Test
    fun `hard and soft iron are recovered from a recording turned through many orientations`() {
        val fit = magnetometerFit(turning(2.5, 90.0))
        val m = (fit as Fit.Done).value
        val offsetError = (m.correction.offset - hardIron).norm()
        // W·K should be a multiple of the identity (the field strength is not observable in the raw data).
        val wk = m.correction.matrix * softIron
        val shapeError = (wk * (1.0 / cbrt(wk.determinant()))).maxDifference(Matrix3.IDENTITY)
        val strengthError = abs(m.fieldStrength - 48.0 * cbrt(softIron.determinant())) / (48.0 * cbrt(softIron.determinant()))
        println("magnetometer: offset error %.3f µT, soft-iron shape error %.4f, strength error %.4f, residual %.3f µT, coverage %.2f, |B| std %.2f → %.2f µT"
            .format(offsetError, shapeError, strengthError, m.residualRms, m.coverage, m.magnitudeStdBefore, m.magnitudeStdAfter))
        assertTrue(offsetError < 0.5, "offset error $offsetError µT")
        assertTrue(shapeError < 0.01, "soft-iron error $shapeError")
        assertTrue(strengthError < 0.01, "field strength error $strengthError")
        assertTrue(m.residualRms < 0.6, "residual ${m.residualRms} for 0.4 µT noise")
        assertTrue(m.coverage > 0.6, "coverage ${m.coverage}")
        assertTrue(m.magnitudeStdAfter < 0.1 * m.magnitudeStdBefore)
        assertTrue(m.correction.matrix.isSymmetric(1e-12))
    }

    @Test
    fun `a recording that turns too little is refused for poor coverage`() {
        for (rate in listOf(0.08, 0.2)) {
            val fit = magnetometerFit(turning(rate, 30.0))
            println("turning at $rate rad/s for 30 s: $fit")
            assertTrue(fit is Fit.Refused && "directions" in fit.reason, "got $fit")
        }
        // Turns that locate the centre well but leave most of the sphere unvisited: refused for coverage alone.
        val partial = magnetometerFit(turning(1.5, 60.0))
        println("turning at 1.5 rad/s for 60 s: $partial")
        assertTrue(partial is Fit.Refused && "of the sphere (at least 30 % needed)" in partial.reason, "got $partial")
        val accepted = magnetometerFit(turning(1.5, 60.0), CalibrationSettings(minCoverage = 0.2))
        assertTrue(accepted is Fit.Done && accepted.value.coverage in 0.2..0.3 && (accepted.value.correction.offset - hardIron).norm() < 2.0, "got $accepted")
    }

    @Test
    fun `the sphere model recovers the hard iron alone`() {
        val s = turning(2.5, 90.0).copy(magSoftIron = Matrix3.IDENTITY)
        val m = (magnetometerFit(s, CalibrationSettings(magModel = EllipsoidModel.SPHERE)) as Fit.Done).value
        assertTrue((m.correction.offset - hardIron).norm() < 0.3)
        assertEquals(48.0, m.fieldStrength, 0.2)
        assertTrue(m.correction.matrix.maxDifference(Matrix3.IDENTITY) < 1e-12)
    }

    @Test
    fun `long recordings are thinned evenly and still fit`() {
        val f = MagnetometerFitter(CalibrationSettings(maxMagSamples = 1000), SessionStream.MAGNETOMETER)
        MotionSimulator(turning(2.5, 90.0)).forEach { f.add(it.mag.x, it.mag.y, it.mag.z) }
        val m = (f.fit() as Fit.Done).value
        assertEquals(9000L, m.samples)
        assertTrue((m.correction.offset - hardIron).norm() < 1.5)
    }

    @Test
    fun `gyroscope bias from still periods`() {
        val bias = Vector3(0.01, -0.02, 0.015)
        val s = SimulationSettings(rateHz = 100.0, durationS = 40.0, gyroNoise = 0.004, gyroBias = bias,
            restWindows = listOf(TimeWindow(0.0, 12.0), TimeWindow(25.0, 41.0)))
        val still = StillPeriods(CalibrationSettings())
        MotionSimulator(s).forEach { still.gyroscope(it.timestampNs, it.gyro.x, it.gyro.y, it.gyro.z); still.accelerometer(it.acc.x, it.acc.y, it.acc.z) }
        val g = (still.gyroscopeFit() as Fit.Done).value
        val err = g.bias - bias
        println("gyroscope: bias error (%.2e, %.2e, %.2e) rad/s, std error %s, still %.0f s".format(err.x, err.y, err.z, g.biasStdError, g.stillTimeS))
        for (k in 0 until 3) {
            assertTrue(abs(err[k]) < 1e-4, "axis $k error ${err[k]}")
            assertTrue(abs(err[k]) < 4 * g.biasStdError[k] + 1e-6, "axis $k error ${err[k]} vs std error ${g.biasStdError[k]}")
            assertEquals(0.004, g.noiseStd[k], 0.0004)
        }
        assertTrue(g.stillTimeS in 24.0..28.0, "still ${g.stillTimeS} s of 27 s at rest")
    }

    @Test
    fun `no still period, no bias`() {
        val still = StillPeriods(CalibrationSettings())
        MotionSimulator(SimulationSettings(durationS = 20.0)).forEach { still.gyroscope(it.timestampNs, it.gyro.x, it.gyro.y, it.gyro.z) }
        val fit = still.gyroscopeFit()
        assertTrue(fit is Fit.Refused && "still for 0.0 s" in fit.reason, "got $fit")
    }

    /** Still poses with moving stretches between them, as a user turning the phone from face to face would record. */
    private fun poses(orientations: List<Quaternion>, s: SimulationSettings, still: StillPeriods) {
        var t0 = 0L
        for ((i, q) in orientations.withIndex()) {
            for ((moving, seconds) in listOf(true to 1.5, false to 4.0)) {
                val settings = s.copy(seed = s.seed + 2 * i + (if (moving) 1 else 0), initialOrientation = q, durationS = seconds, angularRate = if (moving) 2.0 else 0.0)
                var last = 0L
                MotionSimulator(settings).forEach {
                    last = t0 + it.timestampNs
                    still.gyroscope(last, it.gyro.x, it.gyro.y, it.gyro.z)
                    still.accelerometer(it.acc.x, it.acc.y, it.acc.z)
                }
                t0 = last + 10_000_000L
            }
        }
    }

    private val faces = listOf(
        Quaternion.IDENTITY, Quaternion.fromAxisAngle(Vector3.UNIT_X, PI), Quaternion.fromAxisAngle(Vector3.UNIT_X, PI / 2),
        Quaternion.fromAxisAngle(Vector3.UNIT_X, -PI / 2), Quaternion.fromAxisAngle(Vector3.UNIT_Y, PI / 2), Quaternion.fromAxisAngle(Vector3.UNIT_Y, -PI / 2),
    )

    @Test
    fun `accelerometer offset and scale from six poses`() {
        val scale = Matrix3.diagonal(1.02, 0.97, 1.01)
        val offset = Vector3(0.12, -0.2, 0.15)
        val s = SimulationSettings(rateHz = 100.0, accNoise = 0.02, accMisalignment = scale, accOffset = offset)
        val still = StillPeriods(CalibrationSettings())
        poses(faces, s, still)
        val a = (still.accelerometerFit() as Fit.Done).value
        val offsetError = (a.correction.offset - offset).norm()
        val scaleError = a.correction.matrix.maxDifference(scale.inverse())
        println("accelerometer (6 poses, %s): offset error %.4f m/s², scale error %.5f".format(a.model, offsetError, scaleError))
        assertEquals(EllipsoidModel.AXIS_ALIGNED, a.model)
        assertEquals(6, a.poses)
        assertTrue(offsetError < 0.01, "offset error $offsetError")
        assertTrue(scaleError < 0.001, "scale error $scaleError")
    }

    @Test
    fun `misalignment too from fourteen poses`() {
        val m = Matrix3.symmetric(1.02, 0.97, 1.01, 0.01, -0.008, 0.012)
        val offset = Vector3(0.12, -0.2, 0.15)
        val s = SimulationSettings(rateHz = 100.0, accNoise = 0.02, accMisalignment = m, accOffset = offset)
        val corners = listOf(1.0, -1.0).flatMap { a -> listOf(1.0, -1.0).flatMap { b -> listOf(1.0, -1.0).map { c -> Vector3(a, b, c).normalized() } } }
            .map { up -> rotationTaking(up, Vector3.UNIT_Z) }
        val still = StillPeriods(CalibrationSettings())
        poses(faces + corners, s, still)
        val a = (still.accelerometerFit() as Fit.Done).value
        val offsetError = (a.correction.offset - offset).norm()
        val matrixError = a.correction.matrix.maxDifference(m.inverse())
        println("accelerometer (14 poses, %s): offset error %.4f m/s², matrix error %.5f, residual %.4f m/s²".format(a.model, offsetError, matrixError, a.residualRms))
        assertEquals(EllipsoidModel.FULL, a.model)
        assertEquals(14, a.poses)
        assertTrue(offsetError < 0.01, "offset error $offsetError")
        assertTrue(matrixError < 0.001, "matrix error $matrixError")
        assertTrue(a.residualRms < 0.01)
    }

    @Test
    fun `too few poses are refused with what to do`() {
        val still = StillPeriods(CalibrationSettings())
        poses(faces.take(3), SimulationSettings(rateHz = 100.0), still)
        val fit = still.accelerometerFit()
        assertTrue(fit is Fit.Refused && "3 distinct still poses" in fit.reason, "got $fit")
    }

    /** A sensor → world rotation under which the device direction [device] points to world [world]. */
    private fun rotationTaking(device: Vector3, world: Vector3): Quaternion {
        val axis = device cross world
        val angle = kotlin.math.acos((device dot world).coerceIn(-1.0, 1.0))
        return if (axis.norm() < 1e-12) Quaternion.IDENTITY else Quaternion.fromAxisAngle(axis, angle)
    }
}
