"""From a finite-element mechanism to its rigid fit, crack, failing body and collapse velocity."""
