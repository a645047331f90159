package dev.motionfusion.app.platform

import android.media.AudioManager
import org.robolectric.annotation.Implementation
import org.robolectric.annotation.Implements
import org.robolectric.shadows.ShadowAudioManager

/**
 * On API 31 to 33 every new window asks AudioManager whether navigation sounds repeat; Robolectric
 * 4.17 answers by building the audio service's binder, whose interface names BluetoothDevice, whose
 * shadow names a class of API 36 that those framework jars lack (NoClassDefFoundError). The answer
 * does not matter to the app, so it is given here without the binder (robolectric.properties).
 */
@Implements(AudioManager::class)
class NavigationSoundsShadow : ShadowAudioManager() {
    @Implementation(minSdk = 31, maxSdk = 33)
    protected fun areNavigationRepeatSoundEffectsEnabled(): Boolean = false
}
