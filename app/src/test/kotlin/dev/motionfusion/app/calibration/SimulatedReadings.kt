package dev.motionfusion.app.calibration

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.calib.Matrix3
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulationSettings
import dev.motionfusion.core.sim.TimeWindow
import kotlinx.coroutines.flow.Flow
import kotlinx.coroutines.flow.asFlow
import kotlin.math.PI

/** A fake [CalibrationSampleSource]: [readings] once, then the flow ends (the screen keeps collecting until Finish). */
class FakeSampleSource(
    private val readings: List<CalibrationSample>,
    override val streams: Set<SessionStream> = setOf(SessionStream.ACCELEROMETER, SessionStream.GYROSCOPE_UNCALIBRATED, SessionStream.MAGNETOMETER_UNCALIBRATED),
) : CalibrationSampleSource {
    var collections = 0
        private set

    override fun samples(): Flow<CalibrationSample> {
        collections++
        return readings.asFlow()
    }
}

/** Readings of the motion simulator with known sensor errors, as the phone would deliver them. */
object SimulatedReadings {
    val hardIron = Vector3(35.0, -20.0, 60.0)
    val softIron: Matrix3 = Matrix3.symmetric(1.15, 0.9, 1.05, 0.06, -0.04, 0.08)
    val accScale: Matrix3 = Matrix3.diagonal(1.02, 0.97, 1.01)
    val accOffset = Vector3(0.12, -0.2, 0.15)
    val gyroBias = Vector3(0.01, -0.02, 0.015)

    /** The phone turned at up to [angularRate] rad/s for [seconds] at 50 Hz in a 48 µT field with hard and soft iron. */
    fun turning(angularRate: Double, seconds: Double, seed: Long = 3L): List<CalibrationSample> {
        val s = SimulationSettings(
            seed = seed, rateHz = 50.0, durationS = seconds, angularRate = angularRate, magNoise = 0.4,
            magSoftIron = softIron, hardIron = hardIron, hardIronWindow = TimeWindow(0.0, seconds + 1.0),
        )
        val out = ArrayList<CalibrationSample>()
        MotionSimulator(s).forEach { out += CalibrationSample(SessionStream.MAGNETOMETER_UNCALIBRATED, 1_000_000_000L + it.timestampNs, it.mag.x, it.mag.y, it.mag.z) }
        return out
    }

    /** The six faces in the order the screen asks for them (screen up, down, standing, upside down, left edge, right edge down). */
    val faces: List<Quaternion> = listOf(
        Quaternion.IDENTITY, Quaternion.fromAxisAngle(Vector3.UNIT_X, PI),
        Quaternion.fromAxisAngle(Vector3.UNIT_X, PI / 2), Quaternion.fromAxisAngle(Vector3.UNIT_X, -PI / 2),
        Quaternion.fromAxisAngle(Vector3.UNIT_Y, -PI / 2), Quaternion.fromAxisAngle(Vector3.UNIT_Y, PI / 2),
    )

    /** The phone moved for 1.5 s, then held still for [holdS] on each of [orientations], at 100 Hz, with accelerometer and gyroscope errors. */
    fun poses(orientations: List<Quaternion>, holdS: Double = 4.0): List<CalibrationSample> {
        val base = SimulationSettings(rateHz = 100.0, accNoise = 0.02, accMisalignment = accScale, accOffset = accOffset, gyroBias = gyroBias, gyroNoise = 0.004)
        val out = ArrayList<CalibrationSample>()
        var t0 = 1_000_000_000L
        for ((i, q) in orientations.withIndex()) {
            for ((moving, seconds) in listOf(true to 1.5, false to holdS)) {
                val settings = base.copy(seed = 20L + 2 * i + (if (moving) 1 else 0), initialOrientation = q, durationS = seconds, angularRate = if (moving) 2.0 else 0.0)
                var last = t0
                MotionSimulator(settings).forEach {
                    last = t0 + it.timestampNs
                    out += CalibrationSample(SessionStream.GYROSCOPE_UNCALIBRATED, last, it.gyro.x, it.gyro.y, it.gyro.z)
                    out += CalibrationSample(SessionStream.ACCELEROMETER, last, it.acc.x, it.acc.y, it.acc.z)
                }
                t0 = last + 10_000_000L
            }
        }
        return out
    }
}
