package dev.motionfusion.core.calib

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulationSettings
import dev.motionfusion.core.sim.TimeWindow
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import kotlin.math.PI

/** The live views of the fitters that the app's guided calibration draws while samples arrive. */
class CalibrationLiveTest {
    @Test
    fun `cells follow the equal-area grid`() {
        assertEquals(-1, DirectionCoverage.cellOf(0.0, 0.0, 0.0))
        assertEquals(-1, DirectionCoverage.cellOf(Double.NaN, 1.0, 0.0))
        // Straight up: the top band; straight down: the bottom one; scale does not matter.
        assertEquals(DirectionCoverage.BANDS - 1, DirectionCoverage.cellOf(0.0, 0.0, 5.0) / DirectionCoverage.SECTORS)
        assertEquals(0, DirectionCoverage.cellOf(0.0, 0.0, -0.1) / DirectionCoverage.SECTORS)
        // On the equator, +x is at longitude 0: the first sector east of the middle.
        assertEquals(4 * DirectionCoverage.SECTORS + 8, DirectionCoverage.cellOf(48.0, 1e-9, 0.0))
        assertEquals(4 * DirectionCoverage.SECTORS + 12, DirectionCoverage.cellOf(0.0, 1.0, 1e-9))
        val c = DirectionCoverage()
        c.add(1.0, 0.0, 0.0); c.add(2.0, 0.0, 0.0); c.add(0.0, 0.0, 1.0)
        assertEquals(2, c.covered)
        assertEquals(2, c.hits(DirectionCoverage.cellOf(1.0, 0.0, 0.0)))
        assertEquals(2.0 / DirectionCoverage.CELLS, c.fraction)
    }

    @Test
    fun `live coverage grows while turning and ends where the fit's does`() {
        val hardIron = Vector3(35.0, -20.0, 60.0)
        val s = SimulationSettings(
            seed = 3L, rateHz = 100.0, durationS = 90.0, angularRate = 2.5, magNoise = 0.4,
            magSoftIron = Matrix3.symmetric(1.15, 0.9, 1.05, 0.06, -0.04, 0.08), hardIron = hardIron, hardIronWindow = TimeWindow(0.0, 91.0),
        )
        val f = MagnetometerFitter(CalibrationSettings(), SessionStream.MAGNETOMETER)
        assertEquals(0, f.coverage().covered)
        val seen = ArrayList<Double>()
        var n = 0
        MotionSimulator(s).forEach {
            f.add(it.mag.x, it.mag.y, it.mag.z)
            if (++n % 1000 == 0) seen += f.coverage().fraction
        }
        println("live coverage every 10 s: " + seen.joinToString(" ") { "%.2f".format(it) })
        // Raw directions are dominated by the hard iron (60 µT against a 48 µT field): without
        // the live fit most of them would fall in few cells.
        val raw = DirectionCoverage()
        MotionSimulator(s).forEach { raw.add(it.mag.x, it.mag.y, it.mag.z) }
        val m = (f.fit() as Fit.Done).value
        assertEquals(m.coverage, seen.last(), 0.02)
        assertTrue(seen.first() < seen.last(), "coverage grows: $seen")
        assertTrue(raw.fraction < 0.5 * m.coverage, "raw ${raw.fraction} against corrected ${m.coverage}")
    }

    @Test
    fun `poses are counted as they are held, before the input ends`() {
        val still = StillPeriods(CalibrationSettings())
        val faces = listOf(Quaternion.IDENTITY, Quaternion.fromAxisAngle(Vector3.UNIT_X, PI), Quaternion.fromAxisAngle(Vector3.UNIT_X, PI / 2))
        val counts = ArrayList<Int>()
        var t0 = 0L
        for ((i, q) in faces.withIndex()) {
            for ((moving, seconds) in listOf(true to 1.5, false to 4.0)) {
                var last = 0L
                MotionSimulator(SimulationSettings(seed = 10L + 2 * i + (if (moving) 1 else 0), rateHz = 100.0, initialOrientation = q, durationS = seconds, angularRate = if (moving) 2.0 else 0.0)).forEach {
                    last = t0 + it.timestampNs
                    still.gyroscope(last, it.gyro.x, it.gyro.y, it.gyro.z)
                    still.accelerometer(it.acc.x, it.acc.y, it.acc.z)
                }
                t0 = last + 10_000_000L
                if (moving) assertFalse(still.lastWindowStill, "moving pose $i") else {
                    assertTrue(still.lastWindowStill, "still pose $i")
                    assertTrue(still.currentPoseS >= 2.0, "held ${still.currentPoseS} s")
                }
                counts += still.distinctPoses().size
            }
        }
        // Moving: the poses held before; still for 4 s: one more, already while it is held.
        assertEquals(listOf(0, 1, 1, 2, 2, 3), counts)
        val up = still.distinctPoses()[0]
        assertEquals(9.80665, up.z, 0.05)
        // Asking does not end the input: the fit still sees all three.
        assertTrue((still.accelerometerFit() as Fit.Refused).reason.startsWith("3 distinct still poses"))
    }

    @Test
    fun `the device round-trips and the tree is what the file holds`() {
        val c = Calibration(
            gyroscope = GyroscopeCalibration(Vector3(0.01, -0.02, 0.015), SessionStream.GYROSCOPE_UNCALIBRATED, 26.0, 26, Vector3(1e-4, 1e-4, 1e-4), Vector3(0.004, 0.004, 0.004)),
            source = "Motion Fusion 0.1.0 guided calibration", device = "Google Pixel 8; LSM6DSV (STMicro)",
        )
        val text = CalibrationJson.write(c)
        assertTrue("\"device\": \"Google Pixel 8; LSM6DSV (STMicro)\"" in text, text)
        assertEquals(c, CalibrationJson.parse(text, "cal.json"))
        assertEquals("Google Pixel 8; LSM6DSV (STMicro)", CalibrationJson.tree(c)["device"])
        assertFalse("device" in CalibrationJson.write(c.copy(device = "")))
    }
}
