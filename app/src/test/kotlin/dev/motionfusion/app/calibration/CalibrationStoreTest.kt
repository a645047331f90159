package dev.motionfusion.app.calibration

import android.content.Context
import dev.motionfusion.app.HeldDispatcher
import dev.motionfusion.app.offMainThread
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.calib.AccelerometerCalibration
import dev.motionfusion.core.calib.Calibration
import dev.motionfusion.core.calib.CalibrationJson
import dev.motionfusion.core.calib.EllipsoidModel
import dev.motionfusion.core.calib.MagnetometerCalibration
import dev.motionfusion.core.calib.Matrix3
import dev.motionfusion.core.calib.SensorCorrection
import dev.motionfusion.core.session.SessionCalibration
import dev.motionfusion.core.event.SessionStream
import kotlinx.coroutines.CoroutineScope
import kotlinx.coroutines.asCoroutineDispatcher
import kotlinx.coroutines.SupervisorJob
import kotlinx.coroutines.runBlocking
import org.junit.Assert.assertEquals
import org.junit.Assert.assertFalse
import org.junit.Assert.assertNotEquals
import org.junit.Assert.assertNull
import org.junit.Assert.assertTrue
import org.junit.Assert.fail
import org.junit.After
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import java.io.File
import java.io.IOException
import java.util.concurrent.Executors

/** The per-device calibration store: atomic JSON files keyed by device, merged per sensor, and the recorder's and live filter's hooks. */
@RunWith(RobolectricTestRunner::class)
class CalibrationStoreTest {
    private val app = RuntimeEnvironment.getApplication()
    private val dir = offMainThread { File(app.filesDir, "calibration") }
    private val pixel = DeviceKey("Google", "Pixel 8", listOf("accelerometer: LSM6DSV (STMicro)", "magnetometer_uncalibrated: AK09918 (AKM)"))
    private val prefs = offMainThread { app.getSharedPreferences(CalibrationStore.PREFS, Context.MODE_PRIVATE) }

    /** One background thread, tasks in order, as the app's disk executor: a store made after a write reads what was written. */
    private val io = Executors.newSingleThreadExecutor().asCoroutineDispatcher()

    @After
    fun stopIo() {
        runBlocking(io) {} // the writes still queued run before the test ends
        io.close()
    }

    private fun store(device: DeviceKey = pixel, at: File = dir) =
        CalibrationStore({ at }, device, { prefs }, io, CoroutineScope(SupervisorJob())).also { runBlocking { it.awaitLoaded() } }

    private val mag = MagnetometerCalibration(
        SensorCorrection(Vector3(221.1, 66.5, -536.6), Matrix3.symmetric(0.979, 1.022, 1.004, -0.047, -0.037, -0.034)),
        SessionStream.MAGNETOMETER_UNCALIBRATED, EllipsoidModel.FULL, 47.2, 2.4, 0.54, 2810, 23.7, 2.36,
    )
    private val acc = AccelerometerCalibration(
        SensorCorrection(Vector3(0.12, -0.2, 0.15), Matrix3.diagonal(0.98, 1.03, 0.99)), SessionStream.ACCELEROMETER, EllipsoidModel.AXIS_ALIGNED, 9.80665, 6, 0.0,
    )

    @Test
    fun `an accepted calibration survives a restart and belongs to its device only`() {
        runBlocking { store().accept(Calibration(magnetometer = mag, source = "app")) }
        val files = dir.list()!!.toList()
        assertEquals(listOf(pixel.fileName), files) // no temporary file left
        assertTrue(pixel.fileName, pixel.fileName.matches(Regex("google-pixel-8-[0-9a-f]{12}\\.json")))
        val again = store()
        assertEquals(mag, again.calibration.value!!.magnetometer)
        assertEquals(pixel.description, again.calibration.value!!.device)
        // The file is a calibration file `fusion replay --calibration` reads.
        assertEquals(mag, CalibrationJson.parse(File(dir, pixel.fileName).readText(), "cal.json").magnetometer)
        // The same model with other sensors (or a backup restored onto another phone) is another device.
        val other = pixel.copy(sensors = listOf("accelerometer: BMI260 (Bosch)"))
        assertNotEquals(pixel.fileName, other.fileName)
        assertNull(store(other).calibration.value)
    }

    @Test
    fun `each sensor keeps its latest accepted fit`() {
        val s = store()
        runBlocking { s.accept(Calibration(accelerometer = acc)) }
        val newer = mag.copy(residualRms = 1.1)
        val now = runBlocking { s.accept(Calibration(magnetometer = newer, refused = mapOf("gyroscope" to "still for 0.0 s"))) }
        assertEquals(acc, now.accelerometer)
        assertEquals(newer, now.magnetometer)
        assertTrue("refusals are not stored", now.refused.isEmpty())
        assertEquals(now, store().calibration.value)
    }

    @Test
    fun `the live filter gets the calibration only when the setting is on, the recorder always`() {
        val s = store()
        assertNull(s.sessionCalibration())
        runBlocking { s.accept(Calibration(magnetometer = mag, accelerometer = acc)) }
        s.setUseInLiveFilter(false)
        assertNull(s.active.value)
        assertEquals(SessionCalibration(s.calibration.value!!, false), s.sessionCalibration())
        s.setUseInLiveFilter(true)
        assertEquals(mag, s.active.value!!.magnetometer)
        assertEquals(SessionCalibration(s.calibration.value!!, true), s.sessionCalibration())
        val again = store() // persisted, read with the file
        assertTrue(again.useInLiveFilter.value)
        assertEquals(mag, again.active.value!!.magnetometer)
    }

    @Test
    fun `the stored setting is the last choice whatever order the background writes run in`() {
        val held = HeldDispatcher()
        val s = CalibrationStore({ dir }, pixel, { prefs }, held, CoroutineScope(SupervisorJob()))
        held.runNewestFirst() // the first read
        s.setUseInLiveFilter(false)
        s.setUseInLiveFilter(true)
        held.runNewestFirst()
        assertTrue(offMainThread { prefs.getBoolean(CalibrationStore.USE_IN_LIVE_FILTER, false) })
        s.setUseInLiveFilter(true)
        s.setUseInLiveFilter(false)
        held.runNewestFirst()
        assertFalse(offMainThread { prefs.getBoolean(CalibrationStore.USE_IN_LIVE_FILTER, true) })
    }

    @Test
    fun `a damaged file is kept aside with the reason and does not stop the store`() {
        dir.mkdirs()
        File(dir, pixel.fileName).writeText("{\"format\": \"motion-fusion-calibration\", \"format_version\": 1, \"magnetometer\": {\"stream\": \"magnetometer_uncalibrated\", \"offset_uT\": [1, 2]")
        val s = store()
        assertNull(s.calibration.value)
        assertTrue(s.problem!!, s.problem!!.startsWith(pixel.fileName + ":"))
        assertTrue(s.problem!!, s.problem!!.contains("kept as ${pixel.fileName}.damaged"))
        assertTrue(File(dir, pixel.fileName + ".damaged").isFile)
        runBlocking { s.accept(Calibration(accelerometer = acc)) }
        assertEquals(acc, store().calibration.value!!.accelerometer)
    }

    @Test
    fun `a file that cannot be written is reported and the stored calibration is unchanged`() {
        val blocked = File(app.filesDir, "not-a-folder").apply { writeText("x") }
        val s = store(at = blocked)
        try {
            runBlocking { s.accept(Calibration(magnetometer = mag)) }
            fail("expected an IOException")
        } catch (e: IOException) {
            assertTrue(s.problem!!, s.problem!!.startsWith(pixel.fileName + ": "))
        }
        assertNull(s.calibration.value)
        assertFalse(File(blocked, pixel.fileName).exists())
    }
}
