package dev.motionfusion.app.settings

import android.os.Looper
import dev.motionfusion.app.HeldDispatcher
import dev.motionfusion.app.offMainThread
import dev.motionfusion.core.filter.FilterSettings
import kotlinx.coroutines.CoroutineScope
import kotlinx.coroutines.Dispatchers
import kotlinx.coroutines.SupervisorJob
import org.junit.Assert.assertEquals
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import org.robolectric.Shadows.shadowOf

/** The settings repository's background writes: what stays stored is the last change. */
@RunWith(RobolectricTestRunner::class)
class SettingsRepositoryTest {
    private val store = SettingsStore(RuntimeEnvironment.getApplication())

    @Test
    fun `the stored settings are the last change whatever order the background writes run in`() {
        val held = HeldDispatcher()
        val repository = SettingsRepository(store, held, CoroutineScope(SupervisorJob() + Dispatchers.Main.immediate))
        held.runNewestFirst() // the first read
        shadowOf(Looper.getMainLooper()).idle()
        val first = LiveSettings(filter = FilterSettings(beta = 0.1))
        val last = LiveSettings(filter = FilterSettings(beta = 0.3))
        repository.update(first)
        repository.update(last)
        held.runNewestFirst()
        assertEquals(last, offMainThread { store.load() })
        assertEquals(last, repository.settings.value)
    }

    @Test
    fun `the UDP target is kept for the next start, and one given before the store is read wins`() {
        val held = HeldDispatcher()
        val scope = CoroutineScope(SupervisorJob() + Dispatchers.Main.immediate)
        val first = SettingsRepository(store, held, scope)
        held.runNewestFirst()
        shadowOf(Looper.getMainLooper()).idle()
        assertEquals("", first.udpTarget)
        first.rememberUdpTarget("192.168.1.20:9000")
        held.runNewestFirst()
        assertEquals("192.168.1.20:9000", offMainThread { store.loadUdpTarget() })
        val next = SettingsRepository(store, held, scope)
        held.runNewestFirst()
        shadowOf(Looper.getMainLooper()).idle()
        assertEquals("192.168.1.20:9000", next.udpTarget)
        val early = SettingsRepository(store, held, scope)
        early.rememberUdpTarget("laptop.local:9001")
        held.runNewestFirst()
        shadowOf(Looper.getMainLooper()).idle()
        assertEquals("laptop.local:9001", early.udpTarget)
        assertEquals("laptop.local:9001", offMainThread { store.loadUdpTarget() })
    }
}
