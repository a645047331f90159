package dev.motionfusion.core.eval

import dev.motionfusion.core.WorldFrame
import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.filter.FilterSettings
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.assertThrows

class SettingsOverrideTest {
    @Test
    fun `overrides settings by name and rejects unknown names and invalid values`() {
        val s = listOf("beta=0.05", "accRejection=true", "mode=IMU", "outputFrame=NED").fold(FilterSettings()) { acc, o -> SettingsOverride.apply(acc, o) }
        assertEquals(FilterSettings(beta = 0.05, accRejection = true, mode = FilterMode.IMU, outputFrame = WorldFrame.NED), s)
        assertThrows<IllegalArgumentException> { SettingsOverride.apply(s, "gamma=1") }
        assertThrows<IllegalArgumentException> { SettingsOverride.apply(s, "beta=-1") }
        assertThrows<IllegalArgumentException> { SettingsOverride.apply(s, "beta") }
    }
}
