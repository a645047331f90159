package dev.motionfusion.app.platform

import android.content.Context
import android.os.Looper
import android.system.Os
import dev.motionfusion.app.AppGraph
import dev.motionfusion.app.settings.LiveSettings
import dev.motionfusion.app.offMainThread
import dev.motionfusion.app.settings.SettingsStore
import dev.motionfusion.core.filter.FilterSettings
import org.junit.Assert.assertEquals
import org.junit.Assert.assertTrue
import org.junit.Assume.assumeTrue
import org.junit.Before
import org.junit.Test
import org.junit.runner.JUnitCore
import org.junit.runner.Result
import org.junit.runner.RunWith
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import org.robolectric.Shadows.shadowOf
import java.util.concurrent.CountDownLatch

/**
 * The rule every Robolectric test runs under (StrictTestApp, robolectric.properties): disk work
 * on the main thread fails the test. The tests below run Robolectric tests of their own (nested
 * classes, skipped unless run from here) and look at what JUnit reports.
 */
class MainThreadPolicyTest {
    private fun run(c: Class<*>): Result {
        System.setProperty(RUN_HERE, "true")
        try {
            return JUnitCore().run(c)
        } finally {
            System.clearProperty(RUN_HERE)
        }
    }

    @Test
    fun `a Robolectric test that touches the disk on the main thread is reported as failing, at the call`() {
        val result = run(OnMainThread::class.java)
        val report = result.failures.joinToString("\n") { it.trace }
        assertEquals(report, 3, result.runCount)
        assertEquals(report, 3, result.failureCount)
        val failures = result.failures.associate { it.description.methodName to it.exception }
        assertEquals(report, setOf("creates a folder", "reads a file's attributes", "reads the settings"), failures.keys)
        // The nested tests' Android classes come from Robolectric's sandbox class loader: compared by name.
        fun violation(e: Throwable, kind: String) =
            e.message == "StrictMode ThreadPolicy violation" && e.cause?.javaClass?.name == "android.os.strictmode.$kind"
        assertTrue(report, violation(failures.getValue("creates a folder"), "DiskWriteViolation"))
        assertTrue(report, violation(failures.getValue("reads a file's attributes"), "DiskReadViolation"))
        // The app's own paths to its files say so themselves (StrictMode does not see java.io on a JVM).
        val settings = failures.getValue("reads the settings")
        assertTrue(report, settings is IllegalStateException && settings.message == "disk work on the main thread")
    }

    @Test
    fun `the same work off the main thread passes, and so does the app's object graph reading its stores`() {
        val result = run(OffMainThread::class.java)
        assertEquals(2, result.runCount)
        assertEquals(emptyList<Any>(), result.failures.map { it.trace })
    }

    @RunWith(RobolectricTestRunner::class)
    class OnMainThread {
        private val app = RuntimeEnvironment.getApplication()

        @Before
        fun onlyFromOutside() = assumeTrue("run by MainThreadPolicyTest", System.getProperty(RUN_HERE) == "true")

        @Test
        fun `creates a folder`() {
            app.getDir("scratch", Context.MODE_PRIVATE)
        }

        @Test
        fun `reads a file's attributes`() {
            val path = offMainThread { app.getDir("scratch", Context.MODE_PRIVATE).path }
            Os.stat(path)
        }

        @Test
        fun `reads the settings`() {
            SettingsStore(app).load()
        }
    }

    @RunWith(RobolectricTestRunner::class)
    class OffMainThread {
        private val app = RuntimeEnvironment.getApplication()

        @Before
        fun onlyFromOutside() = assumeTrue("run by MainThreadPolicyTest", System.getProperty(RUN_HERE) == "true")

        @Test
        fun `the same work on another thread`() {
            offMainThread {
                Os.stat(app.getDir("scratch", Context.MODE_PRIVATE).path)
                SettingsStore(app).load()
            }
        }

        @Test
        fun `the app's graph is built on the main thread, its stores read on its disk executor`() {
            val stored = LiveSettings(filter = FilterSettings(beta = 0.05))
            offMainThread { SettingsStore(app).save(stored) }
            val graph = AppGraph.create(app)
            // The disk executor runs tasks in order: once this one has run, the stores have been read.
            val done = CountDownLatch(1)
            graph.disk.execute(null) { done.countDown() }
            done.await()
            shadowOf(Looper.getMainLooper()).idle()
            assertEquals(stored, graph.settings.value)
            assertEquals(null, graph.calibrationStore.problem)
        }
    }

    private companion object {
        const val RUN_HERE = "motionfusion.mainThreadPolicyTest"
    }
}
