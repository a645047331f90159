package dev.motionfusion.app.calibration

import android.content.Context
import dev.motionfusion.core.calib.CalibrationSettings
import dev.motionfusion.core.calib.DirectionCoverage
import dev.motionfusion.core.calib.Fit
import dev.motionfusion.core.event.SessionStream
import kotlinx.coroutines.CoroutineScope
import kotlinx.coroutines.Dispatchers
import kotlinx.coroutines.SupervisorJob
import kotlinx.coroutines.asCoroutineDispatcher
import kotlinx.coroutines.flow.first
import kotlinx.coroutines.runBlocking
import kotlinx.coroutines.withTimeout
import org.junit.Assert.assertEquals
import org.junit.Assert.assertFalse
import org.junit.Assert.assertNull
import org.junit.Assert.assertTrue
import org.junit.After
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import java.io.File
import java.util.concurrent.Executors

/**
 * The guided calibration's state on simulated readings with known errors: what it shows while
 * collecting, what it fits (core's fitters), what it stores. Collection runs on the main thread
 * here (Dispatchers.Main.immediate), so each step is complete when the call returns.
 */
@RunWith(RobolectricTestRunner::class)
class CalibrationViewModelTest {
    private val app = RuntimeEnvironment.getApplication()
    /** One background thread, tasks in order, as the app's disk executor; drained when the test ends. */
    private val io = Executors.newSingleThreadExecutor().asCoroutineDispatcher()

    @After
    fun stopIo() {
        runBlocking(io) {}
        io.close()
    }

    private fun store() = CalibrationStore(
        { File(app.filesDir, "calibration") }, DeviceKey("Google", "Pixel 8", listOf("magnetometer_uncalibrated: AK09918 (AKM)")),
        { app.getSharedPreferences("calibration-test", Context.MODE_PRIVATE) }, io, CoroutineScope(SupervisorJob()),
    ).also { runBlocking { it.awaitLoaded() } }

    private fun viewModel(source: CalibrationSampleSource, store: CalibrationStore = store()): CalibrationViewModel {
        return CalibrationViewModel(source, store, CalibrationSettings(maxMagSamples = 20_000), Dispatchers.Main.immediate, io, "test")
    }

    @Test
    fun `magnetometer turn-through fills the map and the fit recovers the hard iron`() {
        val vm = viewModel(FakeSampleSource(SimulatedReadings.turning(2.5, 90.0)))
        assertEquals(CalibrationStage.READY, vm.state.value.stage)
        assertEquals(SessionStream.MAGNETOMETER_UNCALIBRATED, vm.state.value.magStream)
        vm.start()
        val live = vm.state.value
        assertEquals(CalibrationStage.COLLECTING, live.stage)
        // Published every 0.2 s of sensor time (10 readings at 50 Hz): the last publication is at most that old.
        assertTrue("${live.magSamples} readings shown", live.magSamples in 4491L..4500L)
        assertEquals(live.coverage, live.cellHits.count { it > 0 }.toDouble() / DirectionCoverage.CELLS, 1e-12)
        assertTrue("live coverage ${live.coverage}", live.coverage > 0.6)
        vm.finish()
        val done = vm.state.value
        assertEquals(CalibrationStage.RESULT, done.stage)
        val m = (done.magFit as Fit.Done).value
        val error = (m.correction.offset - SimulatedReadings.hardIron).norm()
        println("app magnetometer: offset error %.3f µT, coverage %.2f, residual %.2f µT".format(error, m.coverage, m.residualRms))
        assertTrue("offset error $error µT", error < 0.5)
        assertEquals(m.coverage, done.coverage, 1e-12)
        assertTrue(done.hasAccepted)
    }

    @Test
    fun `a turn-through that covers too little is refused with the reason`() {
        val vm = viewModel(FakeSampleSource(SimulatedReadings.turning(1.5, 60.0)))
        vm.start()
        vm.finish()
        val fit = vm.state.value.magFit
        assertTrue("got $fit", fit is Fit.Refused && "of the sphere" in fit.reason)
        assertFalse(vm.state.value.hasAccepted)
        vm.save() // nothing accepted: nothing stored
        assertFalse(vm.state.value.saved)
    }

    @Test
    fun `poses are asked for one by one and give the accelerometer and the gyroscope bias`() {
        val three = viewModel(FakeSampleSource(SimulatedReadings.poses(SimulatedReadings.faces.take(3))))
        three.select(CalibrationStep.POSES)
        three.start()
        val s = three.state.value
        assertEquals(setOf(PoseFace.SCREEN_UP, PoseFace.SCREEN_DOWN, PoseFace.BOTTOM_EDGE_DOWN), s.facesHeld)
        assertEquals(PoseFace.TOP_EDGE_DOWN, s.askedFace)
        assertEquals(4, s.poseNumber)
        assertTrue(s.still)

        val six = viewModel(FakeSampleSource(SimulatedReadings.poses(SimulatedReadings.faces)))
        six.select(CalibrationStep.POSES)
        six.start()
        assertEquals(PoseFace.entries.toSet(), six.state.value.facesHeld)
        assertNull(six.state.value.askedFace)
        six.finish()
        val r = six.state.value
        val a = (r.accFit as Fit.Done).value
        val g = (r.gyroFit as Fit.Done).value
        val offsetError = (a.correction.offset - SimulatedReadings.accOffset).norm()
        val scaleError = a.correction.matrix.maxDifference(SimulatedReadings.accScale.inverse())
        val biasError = (g.bias - SimulatedReadings.gyroBias).norm()
        println("app poses: accelerometer offset error %.4f m/s², scale error %.5f; gyroscope bias error %.2e rad/s over %.0f s"
            .format(offsetError, scaleError, biasError, g.stillTimeS))
        assertEquals(SessionStream.GYROSCOPE_UNCALIBRATED, g.stream)
        assertTrue("offset error $offsetError", offsetError < 0.01)
        assertTrue("scale error $scaleError", scaleError < 0.001)
        assertTrue("bias error $biasError", biasError < 3e-4)
    }

    @Test
    fun `an accepted fit is stored for the device and a refused one is not`() {
        val store = store()
        val vm = viewModel(FakeSampleSource(SimulatedReadings.turning(2.5, 90.0)), store)
        vm.start(); vm.finish(); vm.save()
        runBlocking { withTimeout(120_000) { vm.state.first { it.saved || it.saveError != null } } } // a guard against a hang only
        assertTrue(vm.state.value.saved)
        val stored = store.calibration.value!!
        assertEquals((vm.state.value.magFit as Fit.Done).value, stored.magnetometer)
        assertNull(stored.accelerometer)
        assertEquals("Google Pixel 8; magnetometer_uncalibrated: AK09918 (AKM)", stored.device)
    }

    @Test
    fun `a device without a gyroscope cannot do the poses and says why`() {
        val vm = viewModel(FakeSampleSource(emptyList(), setOf(SessionStream.ACCELEROMETER, SessionStream.MAGNETOMETER)))
        assertEquals(SessionStream.MAGNETOMETER, vm.state.value.magStream)
        assertNull(vm.state.value.unavailable)
        vm.select(CalibrationStep.POSES)
        assertEquals(dev.motionfusion.app.R.string.calibration_no_gyroscope, vm.state.value.unavailable)
        vm.start()
        assertEquals(CalibrationStage.READY, vm.state.value.stage)
    }
}
